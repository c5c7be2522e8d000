#include "cpu_ref/shade.h"

#include "common/parallel.h"
#include "common/shader_constants.h"

#include <algorithm>

namespace mrr {

namespace {
constexpr float kSky[3] = {kSkyRed, kSkyGreen, kSkyBlue};  // common/shader_constants.h

// The light a pixel receives, per effect (the header lists the formulas).
glm::vec3 lighting(Effect effect, const glm::vec3& lightColor, float nl, const ImageF& e, const ImageU8& lit, int x,
                   int y) {
  switch (effect) {
    case Effect::Ssm: return lightColor * (0.25f + 0.75f * nl * e.at(x, y));
    case Effect::Ssgi:
      return lightColor * (0.1f + 0.9f * nl * static_cast<float>(lit.at(x, y))) +
             glm::vec3(e.at(x, y, 0), e.at(x, y, 1), e.at(x, y, 2));
    case Effect::Ssao: break;
  }
  return lightColor * (0.45f * e.at(x, y) + 0.55f * nl);
}
}  // namespace

ImageF shadeFinal(const GBuffer& g0, const ImageF& effect, const ImageU8& shadowLit, const View& view,
                  const DirectionalLight& light, Effect effectKind) {
  ImageF out(effect.width, effect.height, 3);
  const glm::vec3 toLight = -glm::normalize(view.directionToView(light.direction));
  parallelFor(0, effect.height, [&](int y) {
    for (int x = 0; x < effect.width; ++x) {
      if (!g0.hit.at(x, y)) {
        for (int c = 0; c < 3; ++c) out.at(x, y, c) = kSky[c];
        continue;
      }
      // 1. direct: Lambert N·L; 2. the effect's term
      const float nl = std::max(glm::dot(g0.normalAt(x, y), toLight), 0.0f);
      const glm::vec3 l = lighting(effectKind, light.color, nl, effect, shadowLit, x, y);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = g0.albedo.at(x, y, c) * l[c];
    }
  });
  return out;
}

}  // namespace mrr
