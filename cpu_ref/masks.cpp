#include "cpu_ref/masks.h"

#include "common/parallel.h"
#include "cpu_ref/blend.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/foveation.h"

#include <algorithm>

namespace mrr {

ImageU8 maxPool(const ImageU8& src, int factor) {
  ImageU8 out = ImageU8::uninitialised(src.width / factor, src.height / factor);
  parallelFor(0, out.height, [&](int y) {
    uint8_t* dst = &out.at(0, y);
    if (factor == 2) {  // the pyramid's step: two source rows, pairs along x (vectorises)
      const uint8_t* a = &src.at(0, 2 * y);
      const uint8_t* b = &src.at(0, 2 * y + 1);
      for (int x = 0; x < out.width; ++x)
        dst[x] = std::max(std::max(a[2 * x], a[2 * x + 1]), std::max(b[2 * x], b[2 * x + 1]));
      return;
    }
    for (int x = 0; x < out.width; ++x) {
      uint8_t m = 0;
      for (int j = 0; j < factor; ++j)
        for (int i = 0; i < factor; ++i) m = std::max(m, src.at(x * factor + i, y * factor + j));
      dst[x] = m;
    }
  });
  return out;
}

namespace {
// blurMask's step 1 for row y over columns [x0, x1): Σ_i w_i·M(x+i) from i = −r up, starting at 0,
// clamp-to-edge. Away from the border it is accumulated a tap at a time over the span (which
// vectorises); the clamp is needed only within r of either end. Each pixel's sum is the same
// whichever way, and whatever span it is computed in.
void blurRowHorizontal(const ImageU8& mask, const std::vector<float>& weights, int y, int x0, int x1, float* dst) {
  const int r = static_cast<int>(weights.size() / 2);
  const int w = mask.width;
  const uint8_t* row = &mask.at(0, y);
  std::vector<float> m(row, row + w);  // M as float
  auto clamped = [&](int x) {
    float sum = 0.0f;
    for (int i = -r; i <= r; ++i) sum += weights[static_cast<size_t>(i + r)] * m[static_cast<size_t>(std::clamp(x + i, 0, w - 1))];
    return sum;
  };
  const int inner0 = std::clamp(r, x0, x1), inner1 = std::clamp(w - r, inner0, x1);
  for (int x = x0; x < inner0; ++x) dst[x] = clamped(x);
  for (int x = inner1; x < x1; ++x) dst[x] = clamped(x);
  for (int x = inner0; x < inner1; ++x) dst[x] = 0.0f;
  for (int i = -r; i <= r; ++i) {
    const float wi = weights[static_cast<size_t>(i + r)];
    const float* src = m.data() + i;
    for (int x = inner0; x < inner1; ++x) dst[x] += wi * src[x];
  }
}

// blurMask's step 2 for row y over columns [x0, x1): Σ_i w_i·H(y+i), clamp-to-edge, a row at a
// time so the inner loop runs along memory.
void blurRowVertical(const ImageF& horizontal, const std::vector<float>& weights, int y, int x0, int x1, float* dst) {
  const int r = static_cast<int>(weights.size() / 2);
  for (int x = x0; x < x1; ++x) dst[x] = 0.0f;
  for (int i = -r; i <= r; ++i) {
    const float wi = weights[static_cast<size_t>(i + r)];
    const float* src = &horizontal.at(0, std::clamp(y + i, 0, horizontal.height - 1));
    for (int x = x0; x < x1; ++x) dst[x] += wi * src[x];
  }
}
}  // namespace

ImageF blurMask(const ImageU8& mask, const std::vector<float>& weights) {
  const int w = mask.width, h = mask.height;
  ImageF horizontal = ImageF::uninitialised(w, h), out = ImageF::uninitialised(w, h);
  // 1. horizontal pass, clamp-to-edge
  parallelFor(0, h, [&](int y) { blurRowHorizontal(mask, weights, y, 0, w, &horizontal.at(0, y)); });
  // 2. vertical pass, clamp-to-edge
  parallelFor(0, h, [&](int y) { blurRowVertical(horizontal, weights, y, 0, w, &out.at(0, y)); });
  return out;
}

void reblurMaskRegion(const ImageU8& mask, const std::vector<float>& weights, const std::vector<uint8_t>& changedRows,
                      int changedX0, int changedX1, ImageF& alpha) {
  const int r = static_cast<int>(weights.size() / 2);
  const int w = mask.width, h = mask.height;
  if (changedX0 >= changedX1) return;
  // The rows of a that a change reaches (within r of a changed row) and the rows of H they read
  // (within 2r); the columns within r of the changed span (the vertical pass keeps to its column).
  auto within = [&](int reach) {
    std::vector<int> diff(static_cast<size_t>(h) + 1, 0);
    for (int y = 0; y < h; ++y)
      if (changedRows[static_cast<size_t>(y)]) {
        ++diff[static_cast<size_t>(std::max(0, y - reach))];
        --diff[static_cast<size_t>(std::min(h, y + reach + 1))];
      }
    std::vector<uint8_t> rows(static_cast<size_t>(h));
    for (int y = 0, open = 0; y < h; ++y) rows[static_cast<size_t>(y)] = (open += diff[static_cast<size_t>(y)]) > 0;
    return rows;
  };
  const std::vector<uint8_t> outRows = within(r), hRows = within(2 * r);
  const int x0 = std::max(0, changedX0 - r), x1 = std::min(w, changedX1 + r);
  ImageF horizontal = ImageF::uninitialised(w, h);
  parallelFor(0, h, [&](int y) {
    if (hRows[static_cast<size_t>(y)]) blurRowHorizontal(mask, weights, y, x0, x1, &horizontal.at(0, y));
  });
  parallelFor(0, h, [&](int y) {
    if (outRows[static_cast<size_t>(y)]) blurRowVertical(horizontal, weights, y, x0, x1, &alpha.at(0, y));
  });
}

namespace {
// 2×2 max of a float image (SPEC §12's footprint pyramid).
ImageF maxPoolF(const ImageF& src) {
  ImageF out = ImageF::uninitialised(src.width / 2, src.height / 2);
  parallelFor(0, out.height, [&](int y) {
    for (int x = 0; x < out.width; ++x)
      out.at(x, y) = std::max(std::max(src.at(2 * x, 2 * y), src.at(2 * x + 1, 2 * y)),
                              std::max(src.at(2 * x, 2 * y + 1), src.at(2 * x + 1, 2 * y + 1)));
  });
  return out;
}
}  // namespace

MaskStages maskStages(const ImageU8& edges, const Constants& c, const ImageF* footprint) {
  MaskStages st;
  // 1. mask pyramid: M_0 = E, M_ℓ = maxpool2(M_{ℓ−1}), built through disabled levels too.
  st.geometry[0] = edges;
  for (int l = 1; l < kLevelCount; ++l) st.geometry[static_cast<size_t>(l)] = maxPool(st.geometry[static_cast<size_t>(l - 1)], 2);
  // 1b. mrr-effect (SPEC §12): F_ℓ = maxpool2(F_{ℓ−1}); each enabled level's M_ℓ but the
  // coarsest (whose a ≡ 1) is widened by its reach. The pyramid above stays E's own.
  if (!footprint) return st;
  for (int l = 0; l < kLevelCount; ++l) {
    const size_t li = static_cast<size_t>(l);
    st.footprintMax[li] = l == 0 ? *footprint : maxPoolF(st.footprintMax[li - 1]);
    const LevelConstants& lc = c.levels[li];
    const ImageU8& m = st.geometry[li];
    if (!lc.enabled || l == c.coarsestEnabled) {
      st.widened[li] = m;
    } else if (l < c.effectMask.firstLevel) {
      // SPEC §12.3, the ablation's effect-only arm: a level the effect does not widen holds nothing
      st.widened[li] = c.effectMask.effectOnly ? ImageU8(m.width, m.height, 1, 0) : m;
    } else {
      st.reach[li] = levelReach(m, st.footprintMax[li], lc.scale, c.effectMask.cap);
      st.widened[li] = dilateByReach(m, st.reach[li]);
      if (c.effectMask.effectOnly) st.widened[li] = wideningOnly(st.widened[li], m);  // SPEC §12.3: M'_ℓ ∧ ¬M_ℓ
    }
  }
  return st;
}

void stencilsFromPyramid(Masks& levels, const Constants& c) {
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    MaskLevel& ml = levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    if (l == c.coarsestEnabled) {
      // 2. the coarsest enabled level covers everything: a ≡ 1.
      ml.alpha = ImageF(lc.width, lc.height, 1, 1.0f);
    } else {
      // 2. a_ℓ = G(σ_ℓ²) ∗ M_ℓ
      ml.alpha = blurMask(ml.mask, lc.gaussian);
    }
    // 3. stencil S_ℓ = [a_ℓ > 0]
    ml.stencil = ImageU8::uninitialised(lc.width, lc.height);
    for (size_t i = 0; i < ml.alpha.data.size(); ++i) ml.stencil.data[i] = ml.alpha.data[i] > 0.0f;
  }
  // 4. coverage closure, fine to coarse: S_next ∨= maxpool(S_ℓ), across disabled levels.
  for (int l = 0; l < kLevelCount; ++l) {
    const int next = c.nextCoarserEnabled(l);
    if (!c.levels[static_cast<size_t>(l)].enabled || next < 0) continue;
    const ImageU8 pooled = maxPool(levels[static_cast<size_t>(l)].stencil, 1 << (next - l));
    ImageU8& coarser = levels[static_cast<size_t>(next)].stencil;
    for (size_t i = 0; i < coarser.data.size(); ++i) coarser.data[i] = coarser.data[i] | pooled.data[i];
  }
}

ImageU8 blendReadsReference(const ImageU8& reach, int level, int margin, const Constants& c) {
  const LevelConstants& lc = c.levels[static_cast<size_t>(level)];
  const int s = lc.scale;
  ImageU8 read(lc.width, lc.height, 1, 0);
  for (int qy = 0; qy < lc.height; ++qy)
    for (int qx = 0; qx < lc.width; ++qx) {
      bool any = false;
      // 2. level pixel q' within `margin` of q (the blur's taps) ...
      for (int dy = -margin; dy <= margin && !any; ++dy)
        for (int dx = -margin; dx <= margin && !any; ++dx) {
          const int tx = qx + dx, ty = qy + dy;
          if (tx < 0 || ty < 0 || tx >= lc.width || ty >= lc.height) continue;
          // ... is a bilinear tap of a full-res pixel p that reaches this level: its taps'
          // floor(u) is q' − 1 or q', u = (p − s/2)/s, so p ∈ [q's − s/2, q's + 3s/2) (clamped taps
          // at the border included), within W×H
          for (int py = std::max(0, ty * s - s / 2); py < std::min(c.height, ty * s + 3 * s / 2) && !any; ++py)
            for (int px = std::max(0, tx * s - s / 2); px < std::min(c.width, tx * s + 3 * s / 2) && !any; ++px)
              any = reach.at(px, py) >= level;
        }
      read.at(qx, qy) = any;
    }
  return read;
}

ImageU8 blendReads(const ImageU8& reach, int level, int margin, const Constants& c) {
  const LevelConstants& lc = c.levels[static_cast<size_t>(level)];
  const int s = lc.scale, w = lc.width, h = lc.height;
  // 2a. along x, per full-res row: some p of the row in [qs − s/2, qs + 3s/2) ∩ [0, W) reaches ℓ
  ImageU8 across = ImageU8::uninitialised(w, c.height);
  parallelFor(0, c.height, [&](int y) {
    const uint8_t* r = &reach.at(0, y);
    uint8_t* dst = &across.at(0, y);
    for (int qx = 0; qx < w; ++qx) {
      uint8_t any = 0;
      for (int px = std::max(0, qx * s - s / 2), end = std::min(c.width, qx * s + 3 * s / 2); px < end; ++px)
        any |= static_cast<uint8_t>(r[px] >= level);
      dst[qx] = any;
    }
  });
  // 2b. along y: some such row in [qs − s/2, qs + 3s/2) ∩ [0, H)
  ImageU8 taps(w, h, 1, 0);
  parallelFor(0, h, [&](int qy) {
    uint8_t* dst = &taps.at(0, qy);
    for (int py = std::max(0, qy * s - s / 2), end = std::min(c.height, qy * s + 3 * s / 2); py < end; ++py) {
      const uint8_t* src = &across.at(0, py);
      for (int qx = 0; qx < w; ++qx) dst[qx] |= src[qx];
    }
  });
  if (margin == 0) return taps;
  // 2c. within `margin` level pixels (the blur's taps), along x then y, clipped to the grid
  ImageU8 wide = ImageU8::uninitialised(w, h), read = ImageU8::uninitialised(w, h);
  parallelFor(0, h, [&](int y) {
    const uint8_t* src = &taps.at(0, y);
    uint8_t* dst = &wide.at(0, y);
    for (int x = 0; x < w; ++x) {
      uint8_t any = 0;
      for (int i = std::max(0, x - margin), end = std::min(w - 1, x + margin); i <= end; ++i) any |= src[i];
      dst[x] = any;
    }
  });
  parallelFor(0, h, [&](int y) {
    uint8_t* dst = &read.at(0, y);
    std::fill(dst, dst + w, uint8_t{0});
    for (int j = std::max(0, y - margin), end = std::min(h - 1, y + margin); j <= end; ++j) {
      const uint8_t* src = &wide.at(0, j);
      for (int x = 0; x < w; ++x) dst[x] |= src[x];
    }
  });
  return read;
}

void keepBlendReads(MaskLevel& level) {
  if (level.read.empty()) return;
  for (size_t i = 0; i < level.stencil.data.size(); ++i)
    level.stencil.data[i] = static_cast<uint8_t>(level.stencil.data[i] & level.read.data[i]);
}

void trimToBlend(Masks& levels, const Constants& c) {
  // 1. R(p), the coarsest level the blend reads at each full-res pixel, from the a-priori S and a
  std::array<LevelImages, kLevelCount> in;
  for (size_t l = 0; l < kLevelCount; ++l) in[l] = {nullptr, &levels[l].stencil, &levels[l].alpha};
  const ImageU8 reach = blendReach(in, c);
  for (int l = 1; l < kLevelCount; ++l) {
    if (!c.levels[static_cast<size_t>(l)].enabled) continue;
    MaskLevel& ml = levels[static_cast<size_t>(l)];
    // 2. D_ℓ: the taps of the pixels with R ≥ ℓ, within SSAO's blur radius
    ml.read = blendReads(reach, l, trimMargin(c), c);
    // 3. S_ℓ ∧= D_ℓ
    keepBlendReads(ml);
  }
}

std::array<MaskLevel, kLevelCount> buildMasks(const ImageU8& edges, const Constants& c, const ImageF* footprint,
                                              const ImageU8* levelLimit) {
  std::array<MaskLevel, kLevelCount> levels;
  // 1, 1b. the pyramid of E, widened by the effect's footprint (mrr-effect)
  MaskStages st = maskStages(edges, c, footprint);
  for (size_t l = 0; l < levels.size(); ++l) levels[l].mask = std::move(footprint ? st.widened[l] : st.geometry[l]);
  // 1c. foveation and motion (SPEC §13): M_ℓ = 0 where ℓ < ℓ_min, the pyramid already built.
  if (levelLimit) applyLevelLimit(levels, *levelLimit, c);
  // 2–4. blur, stencil, closure
  stencilsFromPyramid(levels, c);
  // 5. mrr-effect's trim (SPEC §12.5): each level ℓ ≥ 1 only where the blend reads it
  if (footprint && c.effectMask.trim) trimToBlend(levels, c);
  return levels;
}

}  // namespace mrr
