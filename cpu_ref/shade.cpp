#include "cpu_ref/shade.h"

#include <tbb/parallel_for.h>

#include <algorithm>

namespace mrr {

namespace {
constexpr float kAmbient = 0.45f;  // share of the light that is ambient (what AO scales)
constexpr float kDirect = 0.55f;   // share that is direct (scaled by N·L)
constexpr float kSky[3] = {0.62f, 0.70f, 0.80f};
}  // namespace

ImageF shadeFinal(const GBuffer& g0, const ImageF& effect, const View& view, const DirectionalLight& light,
                  Effect effectKind) {
  (void)effectKind;  // SSAO: the effect scales the ambient term
  ImageF out(effect.width, effect.height, 3);
  const glm::vec3 toLight = -glm::normalize(view.directionToView(light.direction));
  tbb::parallel_for(0, effect.height, [&](int y) {
    for (int x = 0; x < effect.width; ++x) {
      if (!g0.hit.at(x, y)) {
        for (int c = 0; c < 3; ++c) out.at(x, y, c) = kSky[c];
        continue;
      }
      // 1. direct: Lambert N·L; 2. ambient: scaled by AO
      const float nl = std::max(glm::dot(g0.normalAt(x, y), toLight), 0.0f);
      const float lighting = kAmbient * effect.at(x, y) + kDirect * nl;
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = g0.albedo.at(x, y, c) * light.color[c] * lighting;
    }
  });
  return out;
}

}  // namespace mrr
