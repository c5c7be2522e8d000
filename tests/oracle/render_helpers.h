#pragma once
#include <optional>
// Renders a scene with the oracle for a test: one call, everything kept.
#include <memory>
#include <string>

#include "common/params.h"
#include "cpu_ref/pipeline.h"
#include "scenes/builtin.h"
#include "scenes/catalog.h"

namespace mrr::test {

struct Rendered {
  std::unique_ptr<Scene> scene;
  Camera camera;
  std::unique_ptr<Renderer> renderer;
  FrameResult frame;
  float framedSize = 0.0f;  // what the view frames: the automatic radii's basis (ResolvedScene::framed)
};

inline Settings ssaoSettings(int w, int h, int samples = 16, Mode mode = Mode::Mrr) {
  Settings s = defaultSettings(Effect::Ssao);
  s.width = w;
  s.height = h;
  s.ssao.samples = samples;
  s.mode = mode;
  // Tests of the method's stages: small, cheap frames would often fall back to full under the
  // never-slower rule (SPEC §11), which tests/oracle/peers_test.cpp tests on its own.
  s.neverSlower = false;
  return s;
}

// `lightToward`: --light-dir (a scene without a light otherwise gets one chosen for its view).
inline Rendered renderScene(const std::string& sceneSpec, const Settings& s,
                            const std::optional<glm::vec3>& lightToward = std::nullopt) {
  Rendered r;
  SceneRequest req;
  req.scene = sceneSpec;
  req.lightToward = lightToward;
  req.aspect = static_cast<float>(s.width) / static_cast<float>(s.height);
  ResolvedScene rs = resolveScene(req);
  r.scene = std::make_unique<Scene>(std::move(rs.scene));
  r.camera = rs.camera;
  r.renderer = std::make_unique<Renderer>(*r.scene);
  r.framedSize = rs.framed.size;
  r.frame = r.renderer->render(r.camera, makeConstants(s, r.framedSize));
  return r;
}

inline int64_t countSet(const ImageU8& img) {
  int64_t n = 0;
  for (uint8_t v : img.data) n += v != 0;
  return n;
}

}  // namespace mrr::test
