#include "cpu_ref/edges.h"

#include "common/parallel.h"

#include <algorithm>
#include <cmath>

namespace mrr {

namespace {
// Relative second difference of d = 1/z along one axis (SPEC §2): 0 on any plane, since
// 1/z is affine in screen space there.
float secondDifference(float dMinus, float d, float dPlus) {
  return std::fabs(dMinus - 2.0f * d + dPlus) / d;
}
}  // namespace

EdgeDecision edgeAt(const GBuffer& g, const EdgeSettings& settings, int x, int y, const ImageU8* shadowLit) {
  EdgeDecision e;
  e.hit = g.hit.at(x, y) != 0;
  if (!e.hit) return e;  // background pixels carry no edge; their hit neighbours do
  const glm::vec3 n = g.normalAt(x, y);
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  // 1. normal edge: first derivative, max over the 4-neighbours inside the image.
  for (int k = 0; k < 4; ++k) {
    const int qx = x + dx[k], qy = y + dy[k];
    if (!g.hit.contains(qx, qy)) continue;  // no edge comes from the border
    if (!g.hit.at(qx, qy)) {
      e.backgroundNeighbour = true;  // 3. background edge
      continue;
    }
    e.normalMax = std::max(e.normalMax, 1.0f - glm::dot(n, g.normalAt(qx, qy)));
  }
  // 2. depth edge: second difference of 1/z, where both neighbours exist and are hits.
  const float d = 1.0f / g.depth.at(x, y);
  auto inv = [&](int qx, int qy) { return 1.0f / g.depth.at(qx, qy); };
  auto usable = [&](int qx, int qy) { return g.hit.contains(qx, qy) && g.hit.at(qx, qy); };
  if (usable(x - 1, y) && usable(x + 1, y)) {
    e.takenX = true;
    e.depthSecondX = secondDifference(inv(x - 1, y), d, inv(x + 1, y));
  }
  if (usable(x, y - 1) && usable(x, y + 1)) {
    e.takenY = true;
    e.depthSecondY = secondDifference(inv(x, y - 1), d, inv(x, y + 1));
  }
  // 4. shadow edge: the one-tap shadow test differs from a hit 4-neighbour's (SPEC §2)
  if (shadowLit) {
    e.lit = shadowLit->at(x, y);
    for (int k = 0; k < 4; ++k) {
      const int qx = x + dx[k], qy = y + dy[k];
      if (g.hit.contains(qx, qy) && g.hit.at(qx, qy) && shadowLit->at(qx, qy) != e.lit) e.shadowNeighbourDiffers = true;
    }
  }
  e.normal = e.normalMax > settings.normalThreshold;
  e.shadow = e.shadowNeighbourDiffers;
  e.depth = std::max(e.depthSecondX, e.depthSecondY) > settings.depthThreshold;
  e.background = e.backgroundNeighbour;
  return e;
}

EdgeImages detectEdges(const GBuffer& g, const EdgeSettings& settings, const ImageU8* shadowLit) {
  EdgeImages out;
  if (shadowLit) out.shadow = ImageU8(g.width, g.height);
  out.normal = ImageU8(g.width, g.height);
  out.depth = ImageU8(g.width, g.height);
  out.background = ImageU8(g.width, g.height);
  out.combined = ImageU8(g.width, g.height);
  parallelFor(0, g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      const EdgeDecision e = edgeAt(g, settings, x, y, shadowLit);
      out.normal.at(x, y) = e.normal;
      out.depth.at(x, y) = e.depth;
      out.background.at(x, y) = e.background;
      if (shadowLit) out.shadow.at(x, y) = e.shadow;
      out.combined.at(x, y) = e.normal || e.depth || e.background || e.shadow;  // 5. E = OR of the kinds
    }
  });
  return out;
}

}  // namespace mrr
