// Shadow acne, analytically (docs/spec.md §6.4): a plane lit from 0° to 85° off its
// normal shadows nothing, so the one-tap test and PCSS must give visibility exactly 1 at every
// pixel, at 720p, on both paths. And a surface whose visible side faces away from the light is
// in its own shadow: exactly 0, on both paths (this is where the acne rings were: the normal
// offset and the depth bias cancel on a surface facing away, and the texel grid decided).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "cpu_ref/pipeline.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "scenes/catalog.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

struct LitPlane {
  Scene scene;
  Camera camera;
  Constants constants;
};

// The built-in plane (z = 0, seen from +z) under a light `degrees` off its normal, from an
// azimuth off both texel axes, so the depth gradient runs diagonally across the map's texels.
LitPlane litPlane(float degrees, bool fromBehind = false) {
  SceneRequest request;
  request.scene = "builtin:plane";
  ResolvedScene resolved = resolveScene(request);
  LitPlane p{std::move(resolved.scene), resolved.camera, {}};
  const float theta = glm::radians(degrees), phi = glm::radians(33.0f);
  const glm::vec3 toLight(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  p.scene.light.direction = fromBehind ? toLight : -toLight;
  Settings s = defaultSettings(Effect::Ssm);
  s.width = 1280;
  s.height = 720;
  s.mode = Mode::Full;
  s.neverSlower = false;
  p.constants = makeConstants(s, resolved.framed.size);  // SSM: no radius enters it
  return p;
}

// Counts hit pixels whose value is not `want`; also how many hit pixels there were.
struct Count {
  int64_t hits = 0, off = 0;
};
Count countOff(const FrameResult& f, float want) {
  Count c;
  const ImageU8& hit = f.levels[0].gbuffer.hit;
  for (int y = 0; y < hit.height; ++y)
    for (int x = 0; x < hit.width; ++x) {
      if (!hit.at(x, y)) continue;
      ++c.hits;
      c.off += f.final().at(x, y) != want || f.shadowLit.at(x, y) != static_cast<uint8_t>(want);
    }
  return c;
}

const float kAngles[] = {0.0f, 15.0f, 30.0f, 45.0f, 60.0f, 75.0f, 85.0f};

TEST(LitPlane, OracleVisibilityIsExactlyOneFrom0To85Degrees) {
  for (float degrees : kAngles) {
    const LitPlane p = litPlane(degrees);
    const Renderer renderer(p.scene);
    const Count c = countOff(renderer.render(p.camera, p.constants), 1.0f);
    EXPECT_GT(c.hits, 1280 * 720 / 2) << degrees << "°";
    EXPECT_EQ(c.off, 0) << "pixels not lit at " << degrees << "° off the normal";
  }
}

TEST(LitPlane, PortVisibilityIsExactlyOneFrom0To85Degrees) {
  MRR_REQUIRE_GL_OR_SKIP();
  for (float degrees : kAngles) {
    const LitPlane p = litPlane(degrees);
    const gpu::GpuRenderer renderer(p.scene);
    const Count c = countOff(renderer.render(p.camera, p.constants), 1.0f);
    EXPECT_GT(c.hits, 1280 * 720 / 2) << degrees << "°";
    EXPECT_EQ(c.off, 0) << "pixels not lit at " << degrees << "° off the normal";
  }
}

TEST(LitPlane, ASurfaceFacingAwayFromTheLightIsExactlyZeroOnBothPaths) {
  for (float degrees : {0.0f, 40.0f, 80.0f}) {
    const LitPlane p = litPlane(degrees, /*fromBehind=*/true);
    const Renderer renderer(p.scene);
    const Count c = countOff(renderer.render(p.camera, p.constants), 0.0f);
    EXPECT_GT(c.hits, 0);
    EXPECT_EQ(c.off, 0) << "oracle, light " << degrees << "° behind";
  }
  MRR_REQUIRE_GL_OR_SKIP();
  for (float degrees : {0.0f, 40.0f, 80.0f}) {
    const LitPlane p = litPlane(degrees, /*fromBehind=*/true);
    const gpu::GpuRenderer renderer(p.scene);
    const Count c = countOff(renderer.render(p.camera, p.constants), 0.0f);
    EXPECT_EQ(c.off, 0) << "port, light " << degrees << "° behind";
  }
}

}  // namespace
}  // namespace mrr
