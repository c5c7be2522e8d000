// Alpha cutouts, analytically (docs/spec.md §1.1): the built-in fence seen square on.
// Each pixel centre's ray meets the fence's plane at a known texture coordinate, so whether it
// stops there or passes through a hole to the wall is known without the renderer; both paths
// must agree with that at every pixel not within a hair of a texel border.
#include <gtest/gtest.h>

#include <cmath>

#include "cpu_ref/pipeline.h"
#include "gpu/pipeline.h"
#include "scenes/catalog.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

constexpr float kFenceDepth = 4.0f;  // the camera stands 4 units before the fence (z = 0)

struct FenceView {
  Scene scene;
  Camera camera;
  Constants constants;
};

FenceView squareOn() {
  SceneRequest request;
  request.scene = "builtin:fence";
  FenceView v{resolveScene(request).scene, lookAt({0.1f, 1.0f, kFenceDepth}, {0.1f, 1.0f, 0.0f}, 40.0f), {}};
  Settings s = defaultSettings(Effect::Ssao);
  s.width = 320;
  s.height = 180;
  s.ssao.samples = 4;
  s.mode = Mode::Full;
  s.neverSlower = false;
  v.constants = makeConstants(s, framedSize(v.scene, v.camera, 320.0f / 180.0f).size);
  return v;
}

struct Tally {
  int checked = 0, wrong = 0, opaque = 0, holes = 0;
};

// Each full-res pixel against the analytic answer: on the fence (depth 4) exactly where the
// cutout is opaque at the ray's texture coordinate.
Tally check(const FenceView& v, const FrameResult& f) {
  const Scene& scene = v.scene;
  const Cutout& cutout = scene.cutouts.at(0);
  const GBuffer& g = f.levels[0].gbuffer;
  Tally t;
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const glm::vec3 d = f.view.worldRay(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
      const glm::vec3 p = f.view.eye + d * (-f.view.eye.z / d.z);  // on the plane z = 0
      if (!(p.x > -2.99f && p.x < 2.99f && p.y > 0.01f && p.y < 1.99f)) continue;
      const float s = (p.x + 3.0f) / 2.0f, tt = 2.0f - p.y;  // the quad's texture coordinates
      const float sx = s * static_cast<float>(cutout.width), ty = tt * static_cast<float>(cutout.height);
      const auto nearBorder = [](float u) { return std::fabs(u - std::round(u)) < 0.02f; };
      if (nearBorder(sx) || nearBorder(ty)) continue;
      const bool opaque = cutout.opaqueAt(s, tt);
      const bool onFence = g.hit.at(x, y) && std::fabs(g.depth.at(x, y) - kFenceDepth) < 1e-3f;
      ++t.checked;
      (opaque ? t.opaque : t.holes)++;
      t.wrong += opaque != onFence;
    }
  return t;
}

void expectExact(const Tally& t, const char* path) {
  EXPECT_GT(t.opaque, 3000) << path;
  EXPECT_GT(t.holes, 10000) << path;
  EXPECT_EQ(t.wrong, 0) << path << ": " << t.wrong << " of " << t.checked << " pixels disagree with the cutout";
}

TEST(Cutout, TexelAddressingWrapsLikeGl) {
  EXPECT_EQ(cutoutTexel(0.0f, 16, Wrap::Repeat), 0);
  EXPECT_EQ(cutoutTexel(0.999f, 16, Wrap::Repeat), 15);
  EXPECT_EQ(cutoutTexel(1.0f, 16, Wrap::Repeat), 0);
  EXPECT_EQ(cutoutTexel(-0.01f, 16, Wrap::Repeat), 15);
  EXPECT_EQ(cutoutTexel(2.5f, 16, Wrap::Repeat), 8);
  EXPECT_EQ(cutoutTexel(-3.0f, 16, Wrap::Clamp), 0);
  EXPECT_EQ(cutoutTexel(7.0f, 16, Wrap::Clamp), 15);
  EXPECT_EQ(cutoutTexel(1.01f, 16, Wrap::Mirror), 15);  // the second period runs backwards
  EXPECT_EQ(cutoutTexel(-0.01f, 16, Wrap::Mirror), 0);
  EXPECT_EQ(cutoutTexel(2.01f, 16, Wrap::Mirror), 0);
  EXPECT_EQ(cutoutTexel(1e30f, 16, Wrap::Repeat), 0);  // huge: kept in int's range, no overflow
  EXPECT_EQ(cutoutTexel(std::nanf(""), 16, Wrap::Repeat), 0);
}

TEST(Cutout, OracleSeesThroughExactlyTheTransparentTexels) {
  const FenceView v = squareOn();
  const Renderer renderer(v.scene);
  expectExact(check(v, renderer.render(v.camera, v.constants)), "oracle");
}

TEST(Cutout, PortSeesThroughExactlyTheTransparentTexels) {
  MRR_REQUIRE_GL_OR_SKIP();
  const FenceView v = squareOn();
  const gpu::GpuRenderer renderer(v.scene);
  expectExact(check(v, renderer.render(v.camera, v.constants)), "port");
}

TEST(Cutout, WithoutItTheQuadIsSolid) {
  // The planted fault: the same scene with the cutout taken away must fail the check above.
  FenceView v = squareOn();
  for (Mesh& mesh : v.scene.meshes) mesh.cutout = -1;
  const Renderer renderer(v.scene);
  EXPECT_GT(check(v, renderer.render(v.camera, v.constants)).wrong, 10000);
}

}  // namespace
}  // namespace mrr
