#include "cpu_ref/effect_masks.h"

#include <algorithm>
#include <cmath>
#include <limits>

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

ImageU8 wideningOnly(const ImageU8& widened, const ImageU8& geometry) {
  ImageU8 out = ImageU8::uninitialised(widened.width, widened.height);
  for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = static_cast<uint8_t>(widened.data[i] && !geometry.data[i]);
  return out;
}

float localRange(const ImageF& c, const ImageU8& stencil, const ImageU8& hit, int x, int y) {
  const int w = c.width, h = c.height;
  if (!stencil.at(x, y) || !hit.at(x, y)) return -1.0f;
  float range = 0.0f;
  for (int ch = 0; ch < c.channels; ++ch) {
    float lo = c.at(x, y, ch), hi = lo;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= w || yy >= h || !stencil.at(xx, yy) || !hit.at(xx, yy)) continue;
        lo = std::min(lo, c.at(xx, yy, ch));
        hi = std::max(hi, c.at(xx, yy, ch));
      }
    range = std::max(range, hi - lo);
  }
  return range;
}

ImageF localRanges(const ImageF& c, const ImageU8& stencil, const ImageU8& hit) {
  ImageF v = ImageF::uninitialised(c.width, c.height);
  parallelFor(0, c.height, [&](int y) {
    for (int x = 0; x < c.width; ++x) v.at(x, y) = localRange(c, stencil, hit, x, y);
  });
  return v;
}

ImageF localRangesSeparable(const ImageF& c, const ImageU8& stencil, const ImageU8& hit) {
  const int w = c.width, h = c.height, ch = c.channels;
  constexpr float kNone = std::numeric_limits<float>::infinity();
  const auto valid = [&](int x, int y) { return stencil.at(x, y) && hit.at(x, y); };
  // 1a. along x: the min and max of each channel over (x − 1 .. x + 1, y), excluded pixels neutral
  ImageF lo = ImageF::uninitialised(w, h, ch), hi = ImageF::uninitialised(w, h, ch);
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < ch; ++k) {
        float a = kNone, b = -kNone;
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= w || !valid(xx, y)) continue;
          a = std::min(a, c.at(xx, y, k));
          b = std::max(b, c.at(xx, y, k));
        }
        lo.at(x, y, k) = a;
        hi.at(x, y, k) = b;
      }
  });
  // 1b. along y: over (x, y − 1 .. y + 1) of those; v = the largest max − min over the channels
  ImageF v = ImageF::uninitialised(w, h);
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      if (!valid(x, y)) {
        v.at(x, y) = -1.0f;
        continue;
      }
      float range = 0.0f;
      for (int k = 0; k < ch; ++k) {
        float a = kNone, b = -kNone;
        for (int dy = -1; dy <= 1; ++dy) {
          const int yy = y + dy;
          if (yy < 0 || yy >= h) continue;
          a = std::min(a, lo.at(x, yy, k));
          b = std::max(b, hi.at(x, yy, k));
        }
        range = std::max(range, b - a);
      }
      v.at(x, y) = range;
    }
  });
  return v;
}

ImageU8 variesAbove(const ImageF& range, float tau) {
  ImageU8 varies = ImageU8::uninitialised(range.width, range.height);
  for (size_t i = 0; i < varies.data.size(); ++i) varies.data[i] = range.data[i] > tau;
  return varies;
}

ImageU8 parentMarks(const ImageU8& varies, int ratio, int finerWidth, int finerHeight) {
  const int w = varies.width, h = varies.height;
  ImageU8 marks = ImageU8::uninitialised(finerWidth, finerHeight);
  parallelFor(0, finerHeight, [&](int y) {
    const int py = std::min(y / ratio, h - 1);
    for (int x = 0; x < finerWidth; ++x) marks.at(x, y) = varies.at(std::min(x / ratio, w - 1), py);
  });
  return marks;
}

ImageU8 refinementMarks(const ImageF& coarser, const ImageU8& coarserStencil, const ImageU8& coarserHit, int ratio,
                        int finerWidth, int finerHeight, float tau) {
  // 1. v(q) > τ at each coarser pixel q, over the shaded hit pixels of its 3×3 neighbourhood (separably)
  const ImageU8 varies = variesAbove(localRangesSeparable(coarser, coarserStencil, coarserHit), tau);
  // 2. each finer pixel takes its coarser parent's mark
  return parentMarks(varies, ratio, finerWidth, finerHeight);
}

void refineMasksReference(MaskLevel& level, const ImageU8& marks, const LevelConstants& lc) {
  // 1. M_ℓ ∨= marks
  for (size_t i = 0; i < level.mask.data.size(); ++i) level.mask.data[i] = level.mask.data[i] | marks.data[i];
  // 2. a_ℓ = G(σ_ℓ²) ∗ M_ℓ
  level.alpha = blurMask(level.mask, lc.gaussian);
  // 3. S_ℓ ∨= [a_ℓ > 0]
  for (size_t i = 0; i < level.alpha.data.size(); ++i)
    level.stencil.data[i] = static_cast<uint8_t>(level.stencil.data[i] | (level.alpha.data[i] > 0.0f));
  // 4. S_ℓ ∧= D_ℓ where the level is trimmed (SPEC §12.5): the blend reads no other pixel
  keepBlendReads(level);
}

void refineMasks(MaskLevel& level, const ImageU8& marks, const LevelConstants& lc) {
  const int w = level.mask.width, h = level.mask.height;
  // 1. M_ℓ ∨= marks, noting the rows and the span of columns where a bit is new
  std::vector<uint8_t> changedRows(static_cast<size_t>(h), 0);
  std::vector<int> rowX0(static_cast<size_t>(h), w), rowX1(static_cast<size_t>(h), 0);
  parallelFor(0, h, [&](int y) {
    uint8_t* m = &level.mask.at(0, y);
    const uint8_t* k = &marks.at(0, y);
    for (int x = 0; x < w; ++x)
      if (k[x] && !m[x]) {
        m[x] = 1;
        changedRows[static_cast<size_t>(y)] = 1;
        rowX0[static_cast<size_t>(y)] = std::min(rowX0[static_cast<size_t>(y)], x);
        rowX1[static_cast<size_t>(y)] = x + 1;
      }
  });
  const int x0 = *std::min_element(rowX0.begin(), rowX0.end()), x1 = *std::max_element(rowX1.begin(), rowX1.end());
  // 2. a_ℓ = G(σ_ℓ²) ∗ M_ℓ, recomputed only where a new bit reaches (blurMask's own sums)
  reblurMaskRegion(level.mask, lc.gaussian, changedRows, x0, x1, level.alpha);
  // 3. S_ℓ ∨= [a_ℓ > 0]
  for (size_t i = 0; i < level.alpha.data.size(); ++i)
    level.stencil.data[i] = static_cast<uint8_t>(level.stencil.data[i] | (level.alpha.data[i] > 0.0f));
  // 4. S_ℓ ∧= D_ℓ where the level is trimmed (SPEC §12.5)
  keepBlendReads(level);
}

}  // namespace mrr
