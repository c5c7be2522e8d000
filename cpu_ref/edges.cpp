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

namespace {
// One interior row of detectEdges (0 < y < h−1, pixels 0 < x < w−1): the decisions edgeAt
// makes, in its order and with its bits, without its border checks. 1/z comes from `inv`
// (computed once per pixel, where edgeAt computes it for each neighbour that asks), and the
// depth test divides once: max(a/d, b/d) = max(a, b)/d exactly, since rounding a division by
// d > 0 is monotonic. tests/oracle/invariants_test.cpp checks every pixel against edgeAt.
struct EdgeRow {
  const uint8_t *hitUp, *hit, *hitDown;
  const float *invUp, *inv, *invDown;
  const float *normalUp, *normal, *normalDown;  // 3 floats per pixel
  const uint8_t *litUp, *lit, *litDown;         // null without shadow edges
};

glm::vec3 normalOf(const float* row, int x) { return {row[3 * x], row[3 * x + 1], row[3 * x + 2]}; }

void interiorRow(const EdgeRow& r, const EdgeSettings& settings, int x0, int x1, uint8_t* normalOut,
                 uint8_t* depthOut, uint8_t* backgroundOut, uint8_t* shadowOut, uint8_t* combinedOut) {
  for (int x = x0; x < x1; ++x) {
    if (!r.hit[x]) {
      normalOut[x] = depthOut[x] = backgroundOut[x] = combinedOut[x] = 0;
      if (shadowOut) shadowOut[x] = 0;
      continue;
    }
    const glm::vec3 n = normalOf(r.normal, x);
    const bool left = r.hit[x - 1], right = r.hit[x + 1], up = r.hitUp[x], down = r.hitDown[x];
    // 1. normal edge, over the hit 4-neighbours in edgeAt's order (left, right, up, down)
    float normalMax = 0.0f;
    if (left) normalMax = std::max(normalMax, 1.0f - glm::dot(n, normalOf(r.normal, x - 1)));
    if (right) normalMax = std::max(normalMax, 1.0f - glm::dot(n, normalOf(r.normal, x + 1)));
    if (up) normalMax = std::max(normalMax, 1.0f - glm::dot(n, normalOf(r.normalUp, x)));
    if (down) normalMax = std::max(normalMax, 1.0f - glm::dot(n, normalOf(r.normalDown, x)));
    // 2. depth edge: the larger numerator of the two second differences, divided once
    const float d = r.inv[x];
    const float numeratorX = left && right ? std::fabs(r.inv[x - 1] - 2.0f * d + r.inv[x + 1]) : 0.0f;
    const float numeratorY = up && down ? std::fabs(r.invUp[x] - 2.0f * d + r.invDown[x]) : 0.0f;
    const bool depth = std::max(numeratorX, numeratorY) / d > settings.depthThreshold;
    // 3. background edge; 4. shadow edge
    const bool background = !(left && right && up && down);
    bool shadow = false;
    if (shadowOut) {
      const uint8_t lit = r.lit[x];
      shadow = (left && r.lit[x - 1] != lit) || (right && r.lit[x + 1] != lit) || (up && r.litUp[x] != lit) ||
               (down && r.litDown[x] != lit);
      shadowOut[x] = shadow;
    }
    const bool normal = normalMax > settings.normalThreshold;
    normalOut[x] = normal;
    depthOut[x] = depth;
    backgroundOut[x] = background;
    combinedOut[x] = normal || depth || background || shadow;  // 5. E = OR of the kinds
  }
}
}  // namespace

EdgeImages detectEdges(const GBuffer& g, const EdgeSettings& settings, const ImageU8* shadowLit) {
  EdgeImages out;
  const int w = g.width, h = g.height;
  // every pixel of each is written below
  if (shadowLit) out.shadow = ImageU8::uninitialised(w, h);
  out.normal = ImageU8::uninitialised(w, h);
  out.depth = ImageU8::uninitialised(w, h);
  out.background = ImageU8::uninitialised(w, h);
  out.combined = ImageU8::uninitialised(w, h);
  auto decideAt = [&](int x, int y) {  // the general path, for the image border
    const EdgeDecision e = edgeAt(g, settings, x, y, shadowLit);
    out.normal.at(x, y) = e.normal;
    out.depth.at(x, y) = e.depth;
    out.background.at(x, y) = e.background;
    if (shadowLit) out.shadow.at(x, y) = e.shadow;
    out.combined.at(x, y) = e.normal || e.depth || e.background || e.shadow;  // 5. E = OR of the kinds
  };
  // d = 1/z once per hit pixel (the same division edgeAt makes; background is never read)
  ImageF inv = ImageF::uninitialised(w, h);
  parallelFor(0, h, [&](int y) {
    const float* z = &g.depth.at(0, y);
    const uint8_t* hit = &g.hit.at(0, y);
    float* dst = &inv.at(0, y);
    for (int x = 0; x < w; ++x) dst[x] = hit[x] ? 1.0f / z[x] : 0.0f;
  });
  parallelFor(0, h, [&](int y) {
    if (y == 0 || y == h - 1 || w < 3) {
      for (int x = 0; x < w; ++x) decideAt(x, y);
      return;
    }
    auto litRow = [&](int row) { return shadowLit ? &shadowLit->at(0, row) : nullptr; };
    const EdgeRow r{&g.hit.at(0, y - 1), &g.hit.at(0, y), &g.hit.at(0, y + 1),
                    &inv.at(0, y - 1),   &inv.at(0, y),   &inv.at(0, y + 1),
                    &g.normal.at(0, y - 1), &g.normal.at(0, y), &g.normal.at(0, y + 1),
                    litRow(y - 1),       litRow(y),       litRow(y + 1)};
    decideAt(0, y);
    interiorRow(r, settings, 1, w - 1, &out.normal.at(0, y), &out.depth.at(0, y), &out.background.at(0, y),
                shadowLit ? &out.shadow.at(0, y) : nullptr, &out.combined.at(0, y));
    decideAt(w - 1, y);
  });
  return out;
}

ImageU8 edgeSample(const GBuffer& g, const EdgeSettings& settings, const ImageU8* shadowLit) {
  constexpr int step = kEdgeSampleStep;
  ImageU8 out((g.width + step - 1) / step, (g.height + step - 1) / step);
  parallelFor(0, out.height, [&](int by) {
    for (int bx = 0; bx < out.width; ++bx) {
      bool any = false;
      for (int i = 0; i < step && !any; ++i) {
        const int x = bx * step + i, y = by * step + i;  // 1. the block's diagonal pixel i, inside the image
        if (x >= g.width || y >= g.height) continue;
        const EdgeDecision e = edgeAt(g, settings, x, y, shadowLit);  // 2. E there (SPEC §2), every kind
        any = e.normal || e.depth || e.background || e.shadow;
      }
      out.at(bx, by) = any;  // 3. Ê: any of them
    }
  });
  return out;
}

}  // namespace mrr
