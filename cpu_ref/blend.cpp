#include "cpu_ref/blend.h"

#include "common/parallel.h"

#include <algorithm>
#include <cmath>

namespace mrr {

namespace {
// floor(u) and u − floor(u) for u = (p + ½)/s − ½ = (2p + 1 − s) / 2s, in integers. Every
// quantity here is a small dyadic rational, so float arithmetic (what a shader does with
// floor()) gives exactly these values. 2s is a power of two: the floor division is an
// arithmetic shift (C++20 defines >> on negative values as floor), the remainder a mask.
void tapCoordinate(int p, int s, int shift, int& base, float& fraction) {
  const int num = 2 * p + 1 - s, den = 2 * s;
  base = num >> shift;
  fraction = static_cast<float>(num & (den - 1)) / static_cast<float>(den);
}
}  // namespace

[[gnu::always_inline]] static inline BilinearTaps tapsOf(int px, int py, const LevelConstants& level) {
  // u = (p + ½)/s − ½ in level coordinates
  int x0 = 0, y0 = 0;
  float tx = 0.0f, ty = 0.0f;
  const int shift = level.index + 1;  // 2s = 2^(ℓ+1)
  tapCoordinate(px, level.scale, shift, x0, tx);
  tapCoordinate(py, level.scale, shift, y0, ty);
  BilinearTaps t;
  const int xs[2] = {std::clamp(x0, 0, level.width - 1), std::clamp(x0 + 1, 0, level.width - 1)};
  const int ys[2] = {std::clamp(y0, 0, level.height - 1), std::clamp(y0 + 1, 0, level.height - 1)};
  const float wx[2] = {1.0f - tx, tx}, wy[2] = {1.0f - ty, ty};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      t.x[j * 2 + i] = xs[i];
      t.y[j * 2 + i] = ys[j];
      t.weight[j * 2 + i] = wx[i] * wy[j];
    }
  return t;
}

BilinearTaps bilinearTaps(int px, int py, const LevelConstants& level) { return tapsOf(px, py, level); }

// The blend's inner loop: inlined there (it runs up to four times per full-res pixel), and
// compiled per channel count (kChannels; 0 = read it from the image), so that the colour
// stays in registers: with the count read at run time it went through the stack, and the
// blend took twice as long.
template <int kChannels>
[[gnu::always_inline]] static inline Upsampled upsampleImpl(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha,
                                                     const LevelConstants& level, int px, int py) {
  const int channels = kChannels > 0 ? kChannels : sub.channels;
  const BilinearTaps t = tapsOf(px, py, level);
  Upsampled u;
  float coverage = 0.0f;
  for (int k = 0; k < 4; ++k) {
    // 1. masked bilinear: only rendered taps (S = 1) carry colour
    // 2. â = Σ b_q a(q), over all taps
    u.alphaHat += t.weight[k] * alpha.at(t.x[k], t.y[k]);
    if (!stencil.at(t.x[k], t.y[k])) continue;  // never read an unrendered value, not even × 0
    const float b = t.weight[k];
    coverage += b;
    const float* texel = &sub.at(t.x[k], t.y[k]);
    for (int c = 0; c < channels; ++c) u.color[c] += b * texel[c];
  }
  if (coverage > 0.0f) {
    u.covered = true;
    // The weights are dyadic, so full coverage sums to 1 exactly, and x / 1 = x.
    if (coverage != 1.0f)
      for (int c = 0; c < channels; ++c) u.color[c] /= coverage;
    // 3. α_ℓ = min(â_ℓ · w_ℓ, 1)
    u.alpha = std::min(u.alphaHat * level.weight, 1.0f);
  } else {
    for (float& c : u.color) c = 0.0f;
    u.alpha = 0.0f;  // the level contributes nothing here
  }
  return u;
}

Upsampled upsampleAt(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level,
                     int px, int py) {
  return upsampleImpl<0>(sub, stencil, alpha, level, px, py);
}

[[gnu::always_inline]] static inline float alphaImpl(const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level,
                                              int px, int py) {
  const BilinearTaps t = tapsOf(px, py, level);
  float coverage = 0.0f, alphaHat = 0.0f;
  for (int k = 0; k < 4; ++k) {
    alphaHat += t.weight[k] * alpha.at(t.x[k], t.y[k]);
    if (stencil.at(t.x[k], t.y[k])) coverage += t.weight[k];
  }
  return coverage > 0.0f ? std::min(alphaHat * level.weight, 1.0f) : 0.0f;  // as upsampleAt
}

float alphaAt(const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level, int px, int py) {
  return alphaImpl(stencil, alpha, level, px, py);
}

float blendStep(float alpha, float fine, float coarserComposite) {
  return alpha * fine + (1.0f - alpha) * coarserComposite;
}

namespace {

// The final image and level map without the per-level images, bit-identical to the full
// pass below: levels are visited fine to coarse for their α first, and only the ones that
// can change the result are upsampled. That is exact because blendStep(1, f, c) = f and
// blendStep(0, f, c) = c in float arithmetic for finite values.
template <int kChannels>
void blendFinalOnly(const std::array<LevelImages, kLevelCount>& levels, const Constants& c, BlendResult& r) {
  constexpr int channels = kChannels;
  // live_ℓ(q) = some a_ℓ > 0 within q's 3×3 neighbourhood: the bilinear taps of every
  // full-res pixel inside level pixel q lie there, so where it is 0, α_ℓ = 0 exactly and the
  // level is skipped with one byte read.
  std::array<ImageU8, kLevelCount> live;
  for (int l = 0; l < c.coarsestEnabled; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const ImageF& a = *levels[static_cast<size_t>(l)].alpha;
    ImageU8& m = live[static_cast<size_t>(l)];
    ImageU8 rows(lc.width, lc.height);  // 3-wide max along x of [a > 0], then along y
    m = ImageU8(lc.width, lc.height);
    parallelFor(0, lc.height, [&](int y) {
      const float* src = &a.at(0, y);
      uint8_t* dst = &rows.at(0, y);
      for (int x = 0; x < lc.width; ++x)
        dst[x] = (src[x] > 0.0f) | (x > 0 && src[x - 1] > 0.0f) | (x + 1 < lc.width && src[x + 1] > 0.0f);
    });
    parallelFor(0, lc.height, [&](int y) {
      const uint8_t* mid = &rows.at(0, y);
      const uint8_t* up = &rows.at(0, std::max(y - 1, 0));
      const uint8_t* down = &rows.at(0, std::min(y + 1, lc.height - 1));
      uint8_t* dst = &m.at(0, y);
      for (int x = 0; x < lc.width; ++x) dst[x] = mid[x] | up[x] | down[x];
    });
  }
  parallelFor(0, c.height, [&](int y) {
    for (int x = 0; x < c.width; ++x) {
      float alphas[kLevelCount] = {0, 0, 0, 0};
      int base = c.coarsestEnabled;  // the finest level whose α is 1: nothing coarser shows
      for (int l = 0; l < c.coarsestEnabled; ++l) {
        const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
        if (!lc.enabled) continue;
        if (!live[static_cast<size_t>(l)].at(x >> lc.index, y >> lc.index)) continue;  // α = 0 (s = 2^ℓ)
        const LevelImages& in = levels[static_cast<size_t>(l)];
        alphas[l] = alphaImpl(*in.stencil, *in.alpha, lc, x, y);
        if (alphas[l] == 1.0f) {
          base = l;
          break;
        }
      }
      const LevelImages& b = levels[static_cast<size_t>(base)];
      const Upsampled bu = upsampleImpl<kChannels>(*b.sub, *b.stencil, *b.alpha, c.levels[static_cast<size_t>(base)], x, y);
      float composite[4] = {bu.color[0], bu.color[1], bu.color[2], bu.color[3]};
      uint8_t finest = static_cast<uint8_t>(base);
      for (int l = base - 1; l >= 0; --l) {
        if (!c.levels[static_cast<size_t>(l)].enabled || alphas[l] == 0.0f) continue;
        const LevelImages& in = levels[static_cast<size_t>(l)];
        const Upsampled u = upsampleImpl<kChannels>(*in.sub, *in.stencil, *in.alpha, c.levels[static_cast<size_t>(l)], x, y);
        for (int ch = 0; ch < channels; ++ch) composite[ch] = blendStep(alphas[l], u.color[ch], composite[ch]);
        finest = static_cast<uint8_t>(l);
      }
      float* out = &r.final.at(x, y);
      for (int ch = 0; ch < channels; ++ch) out[ch] = composite[ch];
      r.levelMap.at(x, y) = finest;
    }
  });
}

}  // namespace

BlendResult BlendResult::allocate(const Constants& c, int channels, int baseLevel, bool keepStages) {
  BlendResult r;
  const int w = c.width, h = c.height;
  r.levelMap = ImageU8(w, h, 1, static_cast<uint8_t>(baseLevel));
  r.final = ImageF(w, h, channels);
  if (keepStages)
    for (int l = 0; l < kLevelCount; ++l) {
      if (!c.levels[static_cast<size_t>(l)].enabled) continue;
      r.upsampled[static_cast<size_t>(l)] = ImageF(w, h, channels);
      r.alpha[static_cast<size_t>(l)] = ImageF(w, h, 1);
      r.composite[static_cast<size_t>(l)] = ImageF(w, h, channels);
    }
  return r;
}

BlendResult blendLevels(const std::array<LevelImages, kLevelCount>& levels, const Constants& c, bool keepStages) {
  const int w = c.width, h = c.height;
  const int channels = levels[static_cast<size_t>(c.coarsestEnabled)].sub->channels;
  BlendResult r = BlendResult::allocate(c, channels, c.coarsestEnabled, keepStages);
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
        const Upsampled u = upsampleImpl<0>(*in.sub, *in.stencil, *in.alpha, lc, x, y);
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

}  // namespace mrr
