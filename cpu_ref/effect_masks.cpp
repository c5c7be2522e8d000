#include "cpu_ref/effect_masks.h"

#include <algorithm>
#include <cmath>

#include "common/parallel.h"
#include "cpu_ref/masks.h"
#include "cpu_ref/shadowmap.h"

namespace mrr {

ImageF effectFootprint(const GBuffer& g, const ImageU8& edges, const View& view, const ShadowMap* map,
                       const Constants& c) {
  ImageF f(edges.width, edges.height, 1, 0.0f);
  const float scale = c.effectMask.scale;
  if (scale <= 0.0f) return f;  // the ablation's "geometry only": M' = M
  parallelFor(0, f.height, [&](int y) {
    for (int x = 0; x < f.width; ++x) {
      // 1. an edge pixel on geometry, in front of the camera
      if (!edges.at(x, y) || !g.hit.at(x, y)) continue;
      const float z = g.depth.at(x, y);
      if (!(z > 0.0f)) continue;
      // 2. the effect's reach on the receiver, world units
      float reach = 0.0f;
      switch (c.effect) {
        case Effect::Ssao: reach = c.ssao.radius; break;
        case Effect::Ssgi: reach = c.ssgi.radius; break;
        case Effect::Ssm: {
          // The one-tap bound: the map's depth at the receiver's own texel as the blocker.
          const Receiver r = receiverAt(*map, view.toWorld(g.positionAt(x, y)), view.directionToWorld(g.normalAt(x, y)),
                                        c.ssm.biasTexels);
          if (!r.facesLight) break;
          const float blocker = map->depthAt(r.u, r.v);
          if (blocker < r.depth) reach = (r.depth - blocker) * 2.0f * c.ssm.tanHalfAngle;
          break;
        }
      }
      // 3. projected at the pixel's depth, full-res pixels
      f.at(x, y) = scale * (reach * view.focal / z);
    }
  });
  return f;
}

Image<int16_t> levelReach(const ImageU8& mask, const ImageF& footprintMax, int scale, int cap) {
  Image<int16_t> k = Image<int16_t>::uninitialised(mask.width, mask.height);
  const float s = static_cast<float>(scale);
  const float limit = static_cast<float>(cap) + 1.0f;  // keeps the conversion in range
  for (size_t i = 0; i < k.data.size(); ++i) {
    if (!mask.data[i]) {
      k.data[i] = -1;
      continue;
    }
    const float levelPixels = std::min(footprintMax.data[i] / s, limit);  // s = 2^ℓ: exact
    k.data[i] = static_cast<int16_t>(std::min(cap, static_cast<int>(std::floor(levelPixels + 0.5f))));
  }
  return k;
}

ImageU8 dilateByReach(const ImageU8& mask, const Image<int16_t>& reach) {
  const int w = mask.width, h = mask.height;
  int maxReach = -1;
  for (int16_t v : reach.data) maxReach = std::max(maxReach, static_cast<int>(v));
  if (maxReach <= 0) return mask;  // nothing reaches past its own pixel
  // 1. along x: H(x, y) = the largest K(q) of a q in row y with |x − q_x| ≤ K(q), else −1
  Image<int16_t> across = Image<int16_t>::uninitialised(w, h);
  parallelFor(0, h, [&](int y) {
    int16_t* dst = &across.at(0, y);
    std::fill(dst, dst + w, int16_t{-1});
    const int16_t* k = &reach.at(0, y);
    for (int x = 0; x < w; ++x) {
      if (k[x] < 0) continue;
      const int x0 = std::max(0, x - k[x]), x1 = std::min(w - 1, x + k[x]);
      for (int i = x0; i <= x1; ++i) dst[i] = std::max(dst[i], k[x]);
    }
  });
  // 2. along y: M'(x, y) = 1 where some row y' has H(x, y') ≥ |y − y'|
  ImageU8 out = ImageU8::uninitialised(w, h);
  parallelFor(0, h, [&](int y) {
    uint8_t* dst = &out.at(0, y);
    std::fill(dst, dst + w, uint8_t{0});
    for (int d = -maxReach; d <= maxReach; ++d) {
      const int yy = y + d;
      if (yy < 0 || yy >= h) continue;
      const int16_t need = static_cast<int16_t>(std::abs(d));
      const int16_t* src = &across.at(0, yy);
      for (int x = 0; x < w; ++x) dst[x] = static_cast<uint8_t>(dst[x] | (src[x] >= need));
    }
  });
  return out;
}

ImageU8 refinementMarks(const ImageF& coarser, const ImageU8& coarserStencil, const ImageU8& coarserHit, int ratio,
                        int finerWidth, int finerHeight, float tau) {
  const int w = coarser.width, h = coarser.height, channels = coarser.channels;
  // 1. v(q) > τ at each coarser pixel q, over the shaded hit pixels of its 3×3 neighbourhood
  ImageU8 varies(w, h, 1, 0);
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      if (!coarserStencil.at(x, y) || !coarserHit.at(x, y)) continue;
      float range = 0.0f;
      for (int ch = 0; ch < channels; ++ch) {
        float lo = coarser.at(x, y, ch), hi = lo;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= w || yy >= h || !coarserStencil.at(xx, yy) || !coarserHit.at(xx, yy)) continue;
            lo = std::min(lo, coarser.at(xx, yy, ch));
            hi = std::max(hi, coarser.at(xx, yy, ch));
          }
        range = std::max(range, hi - lo);
      }
      varies.at(x, y) = range > tau;
    }
  });
  // 2. each finer pixel takes its coarser parent's mark
  ImageU8 marks = ImageU8::uninitialised(finerWidth, finerHeight);
  parallelFor(0, finerHeight, [&](int y) {
    const int py = std::min(y / ratio, h - 1);
    for (int x = 0; x < finerWidth; ++x) marks.at(x, y) = varies.at(std::min(x / ratio, w - 1), py);
  });
  return marks;
}

void refineMasks(MaskLevel& level, const ImageU8& marks, const LevelConstants& lc) {
  // 1. M_ℓ ∨= marks
  for (size_t i = 0; i < level.mask.data.size(); ++i) level.mask.data[i] = level.mask.data[i] | marks.data[i];
  // 2. a_ℓ = G(σ_ℓ²) ∗ M_ℓ again
  level.alpha = blurMask(level.mask, lc.gaussian);
  // 3. S_ℓ ∨= [a_ℓ > 0]
  for (size_t i = 0; i < level.alpha.data.size(); ++i)
    level.stencil.data[i] = static_cast<uint8_t>(level.stencil.data[i] | (level.alpha.data[i] > 0.0f));
}

}  // namespace mrr
