#include "cpu_ref/blend.h"

#include "common/parallel.h"

#include <algorithm>
#include <cmath>

namespace mrr {

namespace {
// Fast path, equal to step 1 (bilinearTapsReference's floor form): floor(u) and u − floor(u)
// for u = (p − ⌊s/2⌋)/s = 2(p − ⌊s/2⌋) / 2s, in integers. Every
// quantity here is a small dyadic rational, so float arithmetic (what a shader does with
// floor()) gives exactly these values. 2s is a power of two: the floor division is an
// arithmetic shift (C++20 defines >> on negative values as floor), the remainder a mask.
void tapCoordinate(int p, int s, int shift, int& base, float& fraction) {
  const int num = 2 * (p - s / 2), den = 2 * s;
  base = num >> shift;
  fraction = static_cast<float>(num & (den - 1)) / static_cast<float>(den);
}

// One axis of the bilinear lookup: the two taps, clamped to the level's `size`, and their
// weights 1 − t and t.
struct TapAxis {
  int index[2];
  float weight[2];
};

[[gnu::always_inline]] inline TapAxis tapAxis(int p, const LevelConstants& level, int size) {
  int base = 0;
  float t = 0.0f;
  tapCoordinate(p, level.scale, level.index + 1, base, t);  // 2s = 2^(ℓ+1)
  return {{std::clamp(base, 0, size - 1), std::clamp(base + 1, 0, size - 1)}, {1.0f - t, t}};
}

// One level's images resolved for one full-res row: the y half of every tap is the same
// along the row, so the blend works out the two level rows it reads once per row.
struct LevelRow {
  TapAxis y;
  const float* alpha[2];
  const uint8_t* stencil[2];
  const float* sub[2];  // null where only α is wanted
  const LevelConstants* level;
};

[[gnu::always_inline]] inline LevelRow levelRow(const ImageF* sub, const ImageU8& stencil, const ImageF& alpha,
                                                const LevelConstants& level, int py) {
  LevelRow r;
  r.y = tapAxis(py, level, level.height);
  for (int j = 0; j < 2; ++j) {
    r.alpha[j] = &alpha.at(0, r.y.index[j]);
    r.stencil[j] = &stencil.at(0, r.y.index[j]);
    r.sub[j] = sub ? &sub->at(0, r.y.index[j]) : nullptr;
  }
  r.level = &level;
  return r;
}
}  // namespace

BilinearTaps bilinearTapsReference(int px, int py, const LevelConstants& level) {
  // 1. u = (p − ⌊s/2⌋)/s in level coordinates (level pixel x holds full-res pixel x·s + ⌊s/2⌋,
  // SPEC §0), its floor and fraction; tap k = 2j + i is (f + i, f + j) clamped to the level grid,
  // with weight (i ? t.x : 1 − t.x)·(j ? t.y : 1 − t.y)
  const float s = static_cast<float>(level.scale);
  const float ux = static_cast<float>(px - level.scale / 2) / s, uy = static_cast<float>(py - level.scale / 2) / s;
  const float fx = std::floor(ux), fy = std::floor(uy);
  const float tx = ux - fx, ty = uy - fy;
  BilinearTaps t;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int k = j * 2 + i;
      t.x[k] = std::clamp(static_cast<int>(fx) + i, 0, level.width - 1);
      t.y[k] = std::clamp(static_cast<int>(fy) + j, 0, level.height - 1);
      t.weight[k] = (i == 1 ? tx : 1.0f - tx) * (j == 1 ? ty : 1.0f - ty);
    }
  return t;
}

Upsampled upsampleReference(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha,
                            const LevelConstants& level, int px, int py) {
  const BilinearTaps taps = bilinearTapsReference(px, py, level);
  Upsampled u;
  float coverage = 0.0f;
  for (int k = 0; k < 4; ++k) {
    const float b = taps.weight[k];
    // 2. â = Σ b_q a(q) over all taps; ĉ and the coverage over the rendered taps (S = 1) only
    u.alphaHat += b * alpha.at(taps.x[k], taps.y[k]);
    if (!stencil.at(taps.x[k], taps.y[k])) continue;  // an unrendered value is never read
    coverage += b;
    for (int c = 0; c < sub.channels; ++c) u.color[c] += b * sub.at(taps.x[k], taps.y[k], c);
  }
  if (coverage > 0.0f) {
    u.covered = true;
    if (coverage != 1.0f)  // x / 1 = x: the fast path skips the division there, to the same bits
      for (int c = 0; c < sub.channels; ++c) u.color[c] /= coverage;
    // 3. α = min(â·w, 1)
    u.alpha = std::min(u.alphaHat * level.weight, 1.0f);
  }
  return u;  // 3. no rendered tap: ĉ = 0, α = 0 (the level contributes nothing here)
}

BlendResult blendReference(const std::array<LevelImages, kLevelCount>& levels, const Constants& c) {
  const int channels = levels[static_cast<size_t>(c.coarsestEnabled)].sub->channels;
  BlendResult r = BlendResult::allocate(c, channels, true);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      float composite[4] = {0, 0, 0, 0};
      int finest = c.coarsestEnabled;
      for (int l = c.coarsestEnabled; l >= 0; --l) {
        const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
        if (!lc.enabled) continue;
        const LevelImages& in = levels[static_cast<size_t>(l)];
        const Upsampled u = upsampleReference(*in.sub, *in.stencil, *in.alpha, lc, x, y);
        const bool coarsest = l == c.coarsestEnabled;  // it covers every pixel: the base, α = 1
        const float alpha = coarsest ? (u.covered ? 1.0f : 0.0f) : u.alpha;
        for (int ch = 0; ch < channels; ++ch)  // 4. c'_ℓ = α ĉ_ℓ + (1 − α) c'_coarser
          composite[ch] = coarsest ? u.color[ch] : blendStep(alpha, u.color[ch], composite[ch]);
        if (!coarsest && alpha > 0.0f) finest = l;  // 5. the finest level with α > 0
        r.alpha[static_cast<size_t>(l)].at(x, y) = alpha;
        for (int ch = 0; ch < channels; ++ch) {
          r.upsampled[static_cast<size_t>(l)].at(x, y, ch) = u.color[ch];
          r.composite[static_cast<size_t>(l)].at(x, y, ch) = composite[ch];
        }
      }
      for (int ch = 0; ch < channels; ++ch) r.final.at(x, y, ch) = composite[ch];
      r.levelMap.at(x, y) = static_cast<uint8_t>(finest);
    }
  return r;
}

BilinearTaps bilinearTaps(int px, int py, const LevelConstants& level) {
  // u = (p − ⌊s/2⌋)/s in level coordinates; tap k = 2j + i has weight wx_i · wy_j
  const TapAxis ax = tapAxis(px, level, level.width), ay = tapAxis(py, level, level.height);
  BilinearTaps t;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      t.x[j * 2 + i] = ax.index[i];
      t.y[j * 2 + i] = ay.index[j];
      t.weight[j * 2 + i] = ax.weight[i] * ay.weight[j];
    }
  return t;
}

// Fast path, equal to steps 2–3 (upsampleReference). The blend's inner loop: inlined there (it runs up to four times per full-res pixel), and
// compiled per channel count (kChannels; 0 = `channels` at run time), so that the colour
// stays in registers: with the count read at run time it went through the stack, and the
// blend took twice as long. The taps are visited in bilinearTaps' order (k = 2j + i).
template <int kChannels>
[[gnu::always_inline]] static inline Upsampled upsampleImpl(const LevelRow& row, int channelsAtRunTime, int px) {
  const int channels = kChannels > 0 ? kChannels : channelsAtRunTime;
  const TapAxis ax = tapAxis(px, *row.level, row.level->width);
  Upsampled u;
  float coverage = 0.0f;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const float b = ax.weight[i] * row.y.weight[j];
      const int x = ax.index[i];
      // 2. â = Σ b_q a(q), over all taps; masked bilinear: only rendered taps (S = 1) carry colour
      u.alphaHat += b * row.alpha[j][x];
      if (!row.stencil[j][x]) continue;  // never read an unrendered value, not even × 0
      coverage += b;
      const float* texel = row.sub[j] + static_cast<size_t>(x) * channels;
      for (int c = 0; c < channels; ++c) u.color[c] += b * texel[c];
    }
  if (coverage > 0.0f) {
    u.covered = true;
    // The weights are dyadic, so full coverage sums to 1 exactly, and x / 1 = x.
    if (coverage != 1.0f)
      for (int c = 0; c < channels; ++c) u.color[c] /= coverage;
    // 3. α_ℓ = min(â_ℓ · w_ℓ, 1)
    u.alpha = std::min(u.alphaHat * row.level->weight, 1.0f);
  } else {
    for (float& c : u.color) c = 0.0f;
    u.alpha = 0.0f;  // the level contributes nothing here
  }
  return u;
}

Upsampled upsampleAt(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level,
                     int px, int py) {
  return upsampleImpl<0>(levelRow(&sub, stencil, alpha, level, py), sub.channels, px);
}

[[gnu::always_inline]] static inline float alphaImpl(const LevelRow& row, int px) {
  const TapAxis ax = tapAxis(px, *row.level, row.level->width);
  float coverage = 0.0f, alphaHat = 0.0f;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const float b = ax.weight[i] * row.y.weight[j];
      alphaHat += b * row.alpha[j][ax.index[i]];
      if (row.stencil[j][ax.index[i]]) coverage += b;
    }
  return coverage > 0.0f ? std::min(alphaHat * row.level->weight, 1.0f) : 0.0f;  // as upsampleAt
}

float blendStep(float alpha, float fine, float coarserComposite) {
  return alpha * fine + (1.0f - alpha) * coarserComposite;
}

namespace {

// live_ℓ(q) = some a_ℓ > 0 within q's 3×3 neighbourhood, for every enabled level ℓ ≥ 1 finer
// than the coarsest: the bilinear taps of every full-res pixel inside level pixel q lie there, so
// where it is 0, α_ℓ = 0 exactly and the level is skipped with one byte read. (Level 0 reads its
// own texel: alphaLevelZero.)
std::array<ImageU8, kLevelCount> liveMaps(const std::array<LevelImages, kLevelCount>& levels, const Constants& c) {
  std::array<ImageU8, kLevelCount> live;
  for (int l = 1; l < c.coarsestEnabled; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const ImageF& a = *levels[static_cast<size_t>(l)].alpha;
    ImageU8& m = live[static_cast<size_t>(l)];
    ImageU8 rows = ImageU8::uninitialised(lc.width, lc.height);  // 3-wide max along x of [a > 0], then along y
    m = ImageU8::uninitialised(lc.width, lc.height);
    parallelFor(0, lc.height, [&](int y) {
      const float* src = &a.at(0, y);
      uint8_t* dst = &rows.at(0, y);
      auto at = [&](int x) {  // the neighbours that exist
        return static_cast<uint8_t>((src[x] > 0.0f) | (x > 0 && src[x - 1] > 0.0f) |
                                    (x + 1 < lc.width && src[x + 1] > 0.0f));
      };
      const int last = lc.width - 1;
      dst[0] = at(0);
      for (int x = 1; x < last; ++x)  // inside, without the border tests (vectorises)
        dst[x] = static_cast<uint8_t>((src[x - 1] > 0.0f) | (src[x] > 0.0f) | (src[x + 1] > 0.0f));
      if (last > 0) dst[last] = at(last);
    });
    parallelFor(0, lc.height, [&](int y) {
      const uint8_t* mid = &rows.at(0, y);
      const uint8_t* up = &rows.at(0, std::max(y - 1, 0));
      const uint8_t* down = &rows.at(0, std::min(y + 1, lc.height - 1));
      uint8_t* dst = &m.at(0, y);
      for (int x = 0; x < lc.width; ++x) dst[x] = mid[x] | up[x] | down[x];
    });
  }
  return live;
}

// alphaImpl at level 0 (s = 1): u = p, so tap 0 is p itself with b = 1 and taps 1–3 have b = 0;
// â = 1·a(p) + 0 + 0 + 0 = a(p) and the coverage is [S(p)] for the finite values a holds, so α is
// min(a(p) w, 1) where S(p), else 0, bit for bit (blend.frag's levelZeroSample).
[[gnu::always_inline]] inline float alphaLevelZero(const LevelRow& row, int px) {
  return row.stencil[0][px] ? std::min(row.alpha[0][px] * row.level->weight, 1.0f) : 0.0f;
}

// The finest enabled level whose α is 1 at full-res pixel x of the rows' row (nothing coarser
// shows there: blendStep(1, f, c) = f), else the coarsest; each finer level's α into `alphas`.
// `liveRow[ℓ]`: live_ℓ's row for the enabled levels 1 ≤ ℓ < C (null otherwise).
[[gnu::always_inline]] inline int opaqueBase(const std::array<LevelRow, kLevelCount>& rows,
                                             const std::array<const uint8_t*, kLevelCount>& liveRow, const Constants& c,
                                             int x, float (&alphas)[kLevelCount]) {
  if (c.coarsestEnabled > 0 && c.levels[0].enabled) {
    alphas[0] = alphaLevelZero(rows[0], x);
    if (alphas[0] == 1.0f) return 0;
  }
  for (int l = 1; l < c.coarsestEnabled; ++l) {
    if (!liveRow[static_cast<size_t>(l)]) continue;  // disabled
    if (!liveRow[static_cast<size_t>(l)][x >> l]) continue;  // α = 0 (s = 2^ℓ)
    alphas[l] = alphaImpl(rows[static_cast<size_t>(l)], x);
    if (alphas[l] == 1.0f) return l;
  }
  return c.coarsestEnabled;
}

// Fast path, equal to blendReference's final image and level map (steps 1–5), without the
// per-level images, bit-identical to the full pass below: levels are visited fine to coarse for their α first, and only the ones that
// can change the result are upsampled. That is exact because blendStep(1, f, c) = f and
// blendStep(0, f, c) = c in float arithmetic for finite values.
template <int kChannels>
void blendFinalOnly(const std::array<LevelImages, kLevelCount>& levels, const Constants& c, BlendResult& r) {
  constexpr int channels = kChannels;
  const std::array<ImageU8, kLevelCount> live = liveMaps(levels, c);
  parallelFor(0, c.height, [&](int y) {
    std::array<LevelRow, kLevelCount> rows;
    std::array<const uint8_t*, kLevelCount> liveRow{};
    for (int l = 0; l <= c.coarsestEnabled; ++l) {
      const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
      if (!lc.enabled) continue;
      const LevelImages& in = levels[static_cast<size_t>(l)];
      rows[static_cast<size_t>(l)] = levelRow(in.sub, *in.stencil, *in.alpha, lc, y);
      if (l >= 1 && l < c.coarsestEnabled) liveRow[static_cast<size_t>(l)] = &live[static_cast<size_t>(l)].at(0, y >> lc.index);
    }
    float* out = &r.final.at(0, y);
    uint8_t* levelMap = &r.levelMap.at(0, y);
    for (int x = 0; x < c.width; ++x) {
      float alphas[kLevelCount] = {0, 0, 0, 0};
      const int base = opaqueBase(rows, liveRow, c, x, alphas);  // the finest level whose α is 1
      const Upsampled bu = upsampleImpl<kChannels>(rows[static_cast<size_t>(base)], channels, x);
      float composite[4] = {bu.color[0], bu.color[1], bu.color[2], bu.color[3]};
      uint8_t finest = static_cast<uint8_t>(base);
      for (int l = base - 1; l >= 0; --l) {
        if (alphas[l] == 0.0f) continue;  // also every disabled level
        const Upsampled u = upsampleImpl<kChannels>(rows[static_cast<size_t>(l)], channels, x);
        for (int ch = 0; ch < channels; ++ch) composite[ch] = blendStep(alphas[l], u.color[ch], composite[ch]);
        finest = static_cast<uint8_t>(l);
      }
      for (int ch = 0; ch < channels; ++ch) out[x * channels + ch] = composite[ch];
      levelMap[x] = finest;
    }
  });
}

}  // namespace

BlendResult blendLevels(const std::array<LevelImages, kLevelCount>& levels, const Constants& c, bool keepStages) {
  const int w = c.width, h = c.height;
  const int channels = levels[static_cast<size_t>(c.coarsestEnabled)].sub->channels;
  BlendResult r = BlendResult::allocate(c, channels, keepStages);
  if (!keepStages) {
    if (channels == 1)
      blendFinalOnly<1>(levels, c, r);
    else
      blendFinalOnly<3>(levels, c, r);  // SSGI's RGB (Constants::channels)
    return r;
  }
  // One pass over the pixels; at each, the levels from the coarsest enabled C (c'_C = ĉ_C)
  // to the finest, keeping the running composite in registers.
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      float composite[4] = {0, 0, 0, 0};
      bool coarsest = true;
      uint8_t finest = static_cast<uint8_t>(c.coarsestEnabled);
      for (int l = c.coarsestEnabled; l >= 0; --l) {
        const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
        if (!lc.enabled) continue;
        const LevelImages& in = levels[static_cast<size_t>(l)];
        const Upsampled u = upsampleImpl<0>(levelRow(in.sub, *in.stencil, *in.alpha, lc, y), channels, x);
        // The coarsest level covers every pixel: it is the base the finer ones blend over.
        const float alpha = coarsest ? (u.covered ? 1.0f : 0.0f) : u.alpha;
        for (int ch = 0; ch < channels; ++ch)
          composite[ch] = coarsest ? u.color[ch] : blendStep(alpha, u.color[ch], composite[ch]);
        if (!coarsest && alpha > 0.0f) finest = static_cast<uint8_t>(l);
        coarsest = false;
        if (keepStages) {
          r.alpha[static_cast<size_t>(l)].at(x, y) = alpha;
          for (int ch = 0; ch < channels; ++ch) {
            r.upsampled[static_cast<size_t>(l)].at(x, y, ch) = u.color[ch];
            r.composite[static_cast<size_t>(l)].at(x, y, ch) = composite[ch];
          }
        }
      }
      for (int ch = 0; ch < channels; ++ch) r.final.at(x, y, ch) = composite[ch];
      r.levelMap.at(x, y) = finest;
    }
  });
  return r;
}

ImageU8 blendReach(const std::array<LevelImages, kLevelCount>& levels, const Constants& c) {
  const LevelConstants& l0 = c.levels[0];
  ImageU8 reach(l0.width, l0.height, 1, 0);  // 0 outside W×H, which the blend never draws
  const std::array<ImageU8, kLevelCount> live = liveMaps(levels, c);
  parallelFor(0, c.height, [&](int y) {
    std::array<LevelRow, kLevelCount> rows;
    std::array<const uint8_t*, kLevelCount> liveRow{};
    for (int l = 0; l < c.coarsestEnabled; ++l) {
      const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
      if (!lc.enabled) continue;
      const LevelImages& in = levels[static_cast<size_t>(l)];
      rows[static_cast<size_t>(l)] = levelRow(nullptr, *in.stencil, *in.alpha, lc, y);
      if (l >= 1) liveRow[static_cast<size_t>(l)] = &live[static_cast<size_t>(l)].at(0, y >> lc.index);
    }
    uint8_t* out = &reach.at(0, y);
    for (int x = 0; x < c.width; ++x) {
      float alphas[kLevelCount] = {0, 0, 0, 0};
      out[x] = static_cast<uint8_t>(opaqueBase(rows, liveRow, c, x, alphas));
    }
  });
  return reach;
}

}  // namespace mrr
