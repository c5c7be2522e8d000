#pragma once
// `mrr explore`'s work budget: what one request may ask the renderer to do.
// A request renders its frame and the frame's full-resolution reference (the page shows the
// difference and the measured speedup), so its work is the two frames' estimated work. The unit is
// a sample-pixel: one SSAO sample at one pixel, about 8 ns on this project's 2-core CI VM (the
// oracle at 2 threads; the port on llvmpipe costs about the same). The estimate is an upper bound
// made from the settings alone, before anything is allocated:
//  - every full-res pixel of every frame costs kPerPixel (its G-buffer ray, edges, masks, blend,
//    the shaded image and the page's copies of the stages: measured with 1 sample at 1920×1080);
//  - every pixel a level may shade costs the effect's per-pixel term plus its per-sample term
//    times the samples (SSGI's samples cost about twice SSAO's, SSM's PCF taps a tenth); the
//    method may shade every pixel of every enabled level (Σ 4^-ℓ of W×H), a fallback to full
//    shades W×H, uniform-k W×H / 4^k, tiles at most W×H;
//  - SSM and SSGI render the light's shadow map, kPerShadowTexel per texel.
// Measured against it (docs/explore.md), full-mode frames take 5–9 ns per sample-pixel here and
// the method's frames less (their stencils are sparse): the default budget, 500 M, is a request
// of about 2–4 s at 2 threads.
#include <algorithm>
#include <cmath>

#include "common/params.h"

namespace mrr::explore {

inline constexpr double kDefaultBudgetM = 500.0;  // --budget, in millions of sample-pixels
// A noise-aware probe (/api/noise) renders the oracle's frame once per seed
// (kNoiseRule.seeds, without references): it may take this many requests' budget.
inline constexpr double kNoiseBudgetRequests = 4.0;
inline constexpr double kPerPixel = 150.0;
inline constexpr double kPerShadowTexel = 4.0;

struct EffectWork {
  double perShadedPixel, perSample;
};
inline EffectWork effectWork(Effect e) {
  switch (e) {
    case Effect::Ssao: return {30.0, 1.0};
    case Effect::Ssm: return {20.0, 0.1};
    case Effect::Ssgi: return {30.0, 2.0};
  }
  return {30.0, 1.0};
}

// The most of W×H that a frame of `s` may shade, summed over its levels.
// A blending method's levels overlap (Σ of its enabled levels' shares; the never-slower rule may
// fall back to full); a peer's stencils partition the screen (its finest shaded level's share).
inline double shadedFraction(const Settings& s) {
  const MethodInfo& m = methodInfo(s.mode);
  double sum = 0.0, most = 0.0;
  for (int l = 0; l < kLevelCount; ++l) {
    const bool shaded = m.userLevels ? s.levels[static_cast<size_t>(l)].enabled : (m.shades >> l & 1u) != 0;
    if (!shaded) continue;
    sum += std::ldexp(1.0, -2 * l);
    most = std::max(most, std::ldexp(1.0, -2 * l));
  }
  if (m.peer()) return most;
  return m.neverSlower ? std::max(sum, 1.0) : sum;
}

// One frame's work in sample-pixels, as a + b · samples: {a, b}.
struct WorkLine {
  double fixed = 0.0, perSample = 0.0;
  double at(double samples) const { return fixed + perSample * samples; }
};
inline WorkLine frameWork(const Settings& s) {
  const double pixels = static_cast<double>(s.width) * s.height;
  const double shaded = pixels * shadedFraction(s);
  const EffectWork e = effectWork(s.effect);
  WorkLine w{pixels * kPerPixel + shaded * e.perShadedPixel, shaded * e.perSample};
  if (s.effect != Effect::Ssao) w.fixed += kPerShadowTexel * static_cast<double>(s.ssm.shadowMapSize) * s.ssm.shadowMapSize;
  return w;
}

// A request: the frame and its reference (`reference`: the reference's settings).
inline WorkLine requestWork(const Settings& s, const Settings& reference) {
  const WorkLine a = frameWork(s), b = frameWork(reference);
  return {a.fixed + b.fixed, a.perSample + b.perSample};
}

inline int maxSamplesOf(Effect e) {
  switch (e) {
    case Effect::Ssao: return kMaxSsaoSamples;
    case Effect::Ssm: return kMaxSsmSamples;
    case Effect::Ssgi: return kMaxSsgiSamples;
  }
  return 1;
}

// The most samples the effect takes that keep `w` within `budget` (SSM: a square), 0 if none do.
inline int mostSamplesWithin(const WorkLine& w, double budget, Effect effect) {
  if (w.at(1.0) > budget) return 0;
  double n = w.perSample > 0.0 ? std::floor((budget - w.fixed) / w.perSample) : maxSamplesOf(effect);
  n = std::min(n, static_cast<double>(maxSamplesOf(effect)));
  int most = std::max(1, static_cast<int>(n));
  if (effect == Effect::Ssm) {
    const int side = static_cast<int>(std::floor(std::sqrt(static_cast<double>(most))));
    most = std::max(1, side * side);
  }
  return most;
}

}  // namespace mrr::explore
