#include "cpu_ref/masks.h"

#include "common/parallel.h"
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
  return levels;
}

}  // namespace mrr
