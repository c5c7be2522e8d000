#include "cpu_ref/blend.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace mrr {

BilinearTaps bilinearTaps(int px, int py, const LevelConstants& level) {
  const float inv = 1.0f / static_cast<float>(level.scale);
  // u = (p + ½)/s − ½ in level coordinates
  const float u = (static_cast<float>(px) + 0.5f) * inv - 0.5f;
  const float v = (static_cast<float>(py) + 0.5f) * inv - 0.5f;
  const float fx = std::floor(u), fy = std::floor(v);
  const float tx = u - fx, ty = v - fy;
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
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

Upsampled upsampleAt(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level,
                     int px, int py) {
  const BilinearTaps t = bilinearTaps(px, py, level);
  Upsampled u;
  float coverage = 0.0f;
  for (int k = 0; k < 4; ++k) {
    // 1. masked bilinear: only rendered taps (S = 1) carry colour
    // 2. â = Σ b_q a(q), over all taps
    u.alphaHat += t.weight[k] * alpha.at(t.x[k], t.y[k]);
    if (!stencil.at(t.x[k], t.y[k])) continue;  // never read an unrendered value, not even × 0
    const float b = t.weight[k];
    coverage += b;
    for (int c = 0; c < sub.channels; ++c) u.color[c] += b * sub.at(t.x[k], t.y[k], c);
  }
  if (coverage > 0.0f) {
    u.covered = true;
    for (int c = 0; c < sub.channels; ++c) u.color[c] /= coverage;
    // 3. α_ℓ = min(â_ℓ · w_ℓ, 1)
    u.alpha = std::min(u.alphaHat * level.weight, 1.0f);
  } else {
    for (float& c : u.color) c = 0.0f;
    u.alpha = 0.0f;  // the level contributes nothing here
  }
  return u;
}

float blendStep(float alpha, float fine, float coarserComposite) {
  return alpha * fine + (1.0f - alpha) * coarserComposite;
}

BlendResult blendLevels(const std::array<LevelImages, kLevelCount>& levels, const Constants& c, bool keepStages) {
  BlendResult r;
  const int w = c.width, h = c.height;
  const int channels = levels[static_cast<size_t>(c.coarsestEnabled)].sub->channels;
  r.levelMap = ImageU8(w, h, 1, static_cast<uint8_t>(c.coarsestEnabled));
  r.final = ImageF(w, h, channels);
  if (keepStages)
    for (int l = 0; l < kLevelCount; ++l) {
      if (!c.levels[static_cast<size_t>(l)].enabled) continue;
      r.upsampled[static_cast<size_t>(l)] = ImageF(w, h, channels);
      r.alpha[static_cast<size_t>(l)] = ImageF(w, h, 1);
      r.composite[static_cast<size_t>(l)] = ImageF(w, h, channels);
    }
  // One pass over the pixels; at each, the levels from the coarsest enabled C (c'_C = ĉ_C)
  // to the finest, keeping the running composite in registers.
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      float composite[4] = {0, 0, 0, 0};
      bool coarsest = true;
      uint8_t finest = static_cast<uint8_t>(c.coarsestEnabled);
      for (int l = c.coarsestEnabled; l >= 0; --l) {
        const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
        if (!lc.enabled) continue;
        const LevelImages& in = levels[static_cast<size_t>(l)];
        const Upsampled u = upsampleAt(*in.sub, *in.stencil, *in.alpha, lc, x, y);
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
