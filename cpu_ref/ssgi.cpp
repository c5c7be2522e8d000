#include "cpu_ref/ssgi.h"

#include "common/parallel.h"
#include "common/shader_constants.h"  // kGrazingCosine

#include <algorithm>

#include "cpu_ref/hemisphere.h"
#include "cpu_ref/stencil.h"

namespace mrr {

namespace {
constexpr float kPi = 3.14159265358979323846f;

// Ritschel et al. 2009, Eq. 2: the form factor of a sender patch of area A at distance d,
// A cos θ_s cos θ_r / (π d²). Samples are spread through the ball, not over the senders'
// surfaces, so senders right at the receiver (a crease) are over-represented and 1/d² would
// make them glow: d is clamped to R/4 (docs/spec.md §6.3).
float patchFormFactor(float area, float cosSender, float cosReceiver, float distance2, float minDistance2) {
  return area * cosSender * cosReceiver / (kPi * std::max(distance2, minDistance2));
}
}  // namespace

ImageF directLight(const GBuffer& g, const ShadowMap& map, const View& view, const DirectionalLight& light,
                   float biasTexels) {
  ImageF out(g.width, g.height, 3, 0.0f);
  const glm::vec3 toLight = -glm::normalize(view.directionToView(light.direction));
  parallelFor(0, g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      if (!g.hit.at(x, y)) continue;
      const glm::vec3 n = g.normalAt(x, y);
      const float nl = std::max(glm::dot(n, toLight), 0.0f);
      if (nl == 0.0f) continue;
      const Receiver r = receiverAt(map, view.toWorld(g.positionAt(x, y)), view.directionToWorld(n), biasTexels);
      const float lit = shadowTest(map, r);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = g.albedo.at(x, y, c) * nl * lit * light.color[c];
    }
  });
  return out;
}

glm::vec3 ssgiAt(const GBuffer& g, const ImageF& direct, const View& view, const LevelConstants& level,
                 const Constants::Ssgi& ssgi, int x, int y, SsgiDetail* detail) {
  if (!g.hit.at(x, y)) return glm::vec3(0.0f);
  const glm::vec3 p = g.positionAt(x, y);
  // 1. the hemisphere frame, rotated per pixel (shared with SSAO)
  const SampleFrame frame = sampleFrame(g.normalAt(x, y), x, y, level.index, ssgi.seed);
  const float invScale = 1.0f / static_cast<float>(level.scale);
  const float width = static_cast<float>(g.width), height = static_cast<float>(g.height);
  glm::vec3 sum(0.0f);
  SsgiDetail d;
  d.samples = ssgi.samples;
  float strongest = 0.0f;
  for (const glm::vec3& k : ssgi.kernel) {
    // 2. the sample's projected pixel is the sender
    const glm::vec3 s = p + ssgi.radius * frame.apply(k);
    const glm::vec2 px = view.project(s) * invScale;
    if (!(-s.z > 0.0f && px.x >= 0.0f && px.y >= 0.0f && px.x < width && px.y < height)) {
      ++d.offscreen;
      continue;
    }
    const int ix = nearestLevelTexel(px.x, invScale), iy = nearestLevelTexel(px.y, invScale);  // SPEC §0
    if (!g.hit.at(ix, iy)) {
      ++d.background;
      continue;
    }
    // 3. its direct light through the patch form factor
    const glm::vec3 toSender = g.positionAt(ix, iy) - p;
    const float distance2 = glm::dot(toSender, toSender);
    if (distance2 == 0.0f) continue;
    const float inv = 1.0f / std::sqrt(distance2);
    const float cosReceiver = glm::dot(frame.n, toSender) * inv;
    const float cosSender = -glm::dot(g.normalAt(ix, iy), toSender) * inv;
    if (cosReceiver <= kGrazingCosine || cosSender <= kGrazingCosine) continue;
    const float f = patchFormFactor(ssgi.patchArea, cosSender, cosReceiver, distance2, ssgi.minDistance2);
    const glm::vec3 c(f * direct.at(ix, iy, 0), f * direct.at(ix, iy, 1), f * direct.at(ix, iy, 2));
    sum += c;
    ++d.senders;
    if (detail && c.x + c.y + c.z > strongest) {
      strongest = c.x + c.y + c.z;
      d.strongest = c;
      d.strongestTexel = {ix, iy};
    }
  }
  if (detail) *detail = d;
  return sum;
}

ImageF renderSsgi(const GBuffer& g, const ImageF& direct, const ImageU8& stencil, const View& view,
                  const LevelConstants& level, const Constants::Ssgi& ssgi) {
  ImageF out(g.width, g.height, 3, 0.0f);
  forEachStencilled(stencil, [&](int x, int y) {
    const glm::vec3 e = ssgiAt(g, direct, view, level, ssgi, x, y);
    for (int c = 0; c < 3; ++c) out.at(x, y, c) = e[c];
  });
  return out;
}

}  // namespace mrr
