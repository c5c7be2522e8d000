#include "cpu_ref/peers.h"

#include <algorithm>
#include <cmath>

#include "common/parallel.h"
#include "cpu_ref/bilateral.h"

namespace mrr {

ImageU8 tileRates(const ImageU8& edges) {
  const int tw = (edges.width + kTileSize - 1) / kTileSize, th = (edges.height + kTileSize - 1) / kTileSize;
  // 1. a tile holds an edge: max over its 16×16 pixels of E
  ImageU8 hasEdge(tw, th);
  parallelFor(0, th, [&](int ty) {
    for (int tx = 0; tx < tw; ++tx) {
      uint8_t any = 0;
      for (int y = ty * kTileSize; y < std::min((ty + 1) * kTileSize, edges.height); ++y)
        for (int x = tx * kTileSize; x < std::min((tx + 1) * kTileSize, edges.width); ++x) any |= edges.at(x, y);
      hasEdge.at(tx, ty) = any;
    }
  });
  // 2. rate 0 on edge tiles, 1 beside one (8-neighbourhood), 2 elsewhere
  ImageU8 rates(tw, th);
  for (int ty = 0; ty < th; ++ty)
    for (int tx = 0; tx < tw; ++tx) {
      uint8_t near = 0;
      for (int j = std::max(ty - 1, 0); j <= std::min(ty + 1, th - 1); ++j)
        for (int i = std::max(tx - 1, 0); i <= std::min(tx + 1, tw - 1); ++i) near |= hasEdge.at(i, j);
      rates.at(tx, ty) = hasEdge.at(tx, ty) ? 0 : near ? 1 : 2;
    }
  return rates;
}

std::array<MaskLevel, kLevelCount> tileMasks(const ImageU8& rates, const Constants& c) {
  std::array<MaskLevel, kLevelCount> levels;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    // 3. M_ℓ = rate, S_ℓ = a_ℓ = [rate == ℓ, inside W×H]
    MaskLevel& ml = levels[static_cast<size_t>(l)];
    ml.mask = ImageU8(lc.width, lc.height);
    ml.stencil = ImageU8(lc.width, lc.height);
    ml.alpha = ImageF(lc.width, lc.height);
    const int w = levelExtent(c.width, lc.scale), h = levelExtent(c.height, lc.scale);
    const int perTile = kTileSize / lc.scale;  // level-ℓ pixels per tile side
    parallelFor(0, lc.height, [&](int y) {
      for (int x = 0; x < lc.width; ++x) {
        const uint8_t rate = rates.at(x / perTile, y / perTile);
        ml.mask.at(x, y) = rate;
        const bool shade = rate == l && x < w && y < h;
        ml.stencil.at(x, y) = shade;
        ml.alpha.at(x, y) = shade ? 1.0f : 0.0f;
      }
    });
  }
  return levels;
}

float jointBilateralWeight(float b, bool hitP, float zp, const glm::vec3& np, bool hitQ, float zq, const glm::vec3& nq,
                           const Constants::Bilateral& params) {
  if (hitP != hitQ) return 0.0f;  // geometry never takes background's value, nor the reverse
  if (!hitP) return b;
  // 1. depth similarity, relative to p's depth
  const float dz = (zq - zp) / (params.sigmaDepth * zp);
  // 2. normal similarity (the bilateral blur's, SPEC §4)
  const float cosine = std::max(glm::dot(np, nq), 0.0f);
  // 3. b_q × depth × normal
  return b * std::exp(-dz * dz) * normalSimilarity(cosine, params.normalPower);
}

void jointBilateralAt(const ImageF& sub, const GBuffer& coarse, const GBuffer& full, const LevelConstants& level,
                      const Constants::Bilateral& params, int px, int py, float* out) {
  const BilinearTaps t = bilinearTaps(px, py, level);
  const bool hitP = full.hit.at(px, py) != 0;
  const float zp = full.depth.at(px, py);
  const glm::vec3 np = full.normalAt(px, py);
  float weights[4], sum = 0.0f;
  int nearest = 0;
  for (int k = 0; k < 4; ++k) {
    weights[k] = jointBilateralWeight(t.weight[k], hitP, zp, np, coarse.hit.at(t.x[k], t.y[k]) != 0,
                                      coarse.depth.at(t.x[k], t.y[k]), coarse.normalAt(t.x[k], t.y[k]), params);
    sum += weights[k];
    if (t.weight[k] > t.weight[nearest]) nearest = k;
  }
  for (int ch = 0; ch < sub.channels; ++ch) out[ch] = 0.0f;
  if (sum > 0.0f) {
    // 4. normalised over the four taps
    for (int k = 0; k < 4; ++k)
      for (int ch = 0; ch < sub.channels; ++ch) out[ch] += weights[k] * sub.at(t.x[k], t.y[k], ch);
    for (int ch = 0; ch < sub.channels; ++ch) out[ch] /= sum;
  } else {
    // 5. every weight vanished: the nearest tap
    for (int ch = 0; ch < sub.channels; ++ch) out[ch] = sub.at(t.x[nearest], t.y[nearest], ch);
  }
}

BlendResult composePeer(const std::array<LevelImages, kLevelCount>& levels,
                        const std::array<const GBuffer*, kLevelCount>& gbuffers, const ImageU8& rates,
                        const Constants& c, bool keepStages) {
  const int w = c.width, h = c.height;
  const MethodInfo& method = methodInfo(c.mode);  // uniform-k: its level k, joint-bilateral upsampled
  const bool uniform = method.compose == Compose::JointBilateral;
  const int k = uniform ? method.finestShadedLevel() : 0;
  const int channels = levels[static_cast<size_t>(uniform ? k : 0)].sub->channels;
  BlendResult r = BlendResult::allocate(c, channels, keepStages);
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      float value[4] = {0, 0, 0, 0};
      int from = k;
      if (uniform) {
        jointBilateralAt(*levels[static_cast<size_t>(k)].sub, *gbuffers[static_cast<size_t>(k)], *gbuffers[0],
                         c.levels[static_cast<size_t>(k)], c.bilateral, x, y, value);
      } else {
        // the coarse pixel's value, broadcast to its block, unfiltered
        from = rates.at(x / kTileSize, y / kTileSize);
        const ImageF& sub = *levels[static_cast<size_t>(from)].sub;
        for (int ch = 0; ch < channels; ++ch) value[ch] = sub.at(x >> from, y >> from, ch);
      }
      for (int ch = 0; ch < channels; ++ch) r.final.at(x, y, ch) = value[ch];
      r.levelMap.at(x, y) = static_cast<uint8_t>(from);
      if (!keepStages) continue;
      // ĉ_ℓ, α_ℓ and c'_ℓ as a hard switch: the supplying level has α = 1, the others 0.
      for (int l = 0; l < kLevelCount; ++l) {
        if (!c.levels[static_cast<size_t>(l)].enabled) continue;
        if (l == from) {
          r.alpha[static_cast<size_t>(l)].at(x, y) = 1.0f;
          for (int ch = 0; ch < channels; ++ch) r.upsampled[static_cast<size_t>(l)].at(x, y, ch) = value[ch];
        }
        if (l <= from)
          for (int ch = 0; ch < channels; ++ch) r.composite[static_cast<size_t>(l)].at(x, y, ch) = value[ch];
      }
    }
  });
  return r;
}

}  // namespace mrr
