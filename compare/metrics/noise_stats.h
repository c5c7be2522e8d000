#pragma once
// The statistics of the noise-aware verdict (docs/spec.md §8): Student's t
// distribution, Welch's t-test, Šidák's family-wise correction, and the t interval of a mean.
// Pure functions of numbers; compare/parity/noise.h applies them to images.
#include <cstdint>
#include <string>
#include <vector>

namespace mrr {

// P(T ≤ t) for Student's t with `df` > 0 degrees of freedom (via the regularised incomplete beta
// function; exact to ~1e-12 relative, also far in the tails).
double studentTCdf(double t, double df);
// P(|T| ≥ |t|): the two-sided p-value.
double studentTTwoSided(double t, double df);
// The t with P(|T| ≥ t) = p (0 < p ≤ 1): the two-sided critical value.
double studentTCritical(double p, double df);

// The per-test level that keeps the family-wise false-alarm rate at `alpha` over `tests`
// independent tests: 1 − (1 − α)^(1/m) (Šidák 1967), computed without cancellation.
double sidakLevel(double alpha, int64_t tests);

// Welch's t-test of two means, each with its variance estimate of the MEAN (s²/n) and that
// estimate's degrees of freedom: t = (a − b) / sqrt(va + vb), ν by Welch–Satterthwaite.
struct WelchResult {
  double t = 0.0;
  double df = 0.0;
  double p = 1.0;  // two-sided
};
WelchResult welchTest(double meanA, double varMeanA, double dfA, double meanB, double varMeanB, double dfB);

// The t interval of the mean of `values` at `confidence` (two-sided): mean ± t s / sqrt(n).
struct MeanInterval {
  double mean = 0.0, lo = 0.0, hi = 0.0;
  double sd = 0.0;  // the sample standard deviation
};
MeanInterval meanInterval(const std::vector<double>& values, double confidence);

// What the noise-aware verdict found on one stage (compare/parity/noise.h): the per-pixel test, and the
// bias over the frame and its regions.
struct RegionBias {
  std::string region;     // "frame", "edge band", "level 2"
  int64_t pixels = 0;
  bool relative = true;   // bias as a share of the oracle's mean (false: absolute, the mean is ~0)
  double bias = 0.0;      // (Σ subject − Σ mean) / Σ mean
  double lo = 0.0, hi = 0.0;  // its interval at the family-wise level
  double seedSpread = 0.0;    // the standard deviation of the oracle's own seeds' biases
  bool pass = true;       // the interval holds 0, or |bias| is at most the rule's floor
};

struct NoiseFigures {
  int seeds = 0;              // K
  int64_t pixels = 0;         // pixels tested
  int64_t tests = 0;          // pixels × channels
  double pixelLevel = 0.0;    // the per-test level (Šidák)
  int64_t rejected = 0;       // pixels with a channel rejected
  double shareRejected = 0.0;
  // The pixel with the smallest p (in the stage's own grid), its value, the oracle's mean there
  // and the mean's interval at the per-test level (where the subject's value should lie).
  int worstX = -1, worstY = -1, worstChannel = 0;
  int scale = 1;  // the stage's grid is W/scale x H/scale: describe() names the worst pixel at full res
  double worstT = 0.0, worstP = 1.0, worstValue = 0.0, worstMean = 0.0, worstLo = 0.0, worstHi = 0.0;
  std::vector<RegionBias> biases;
  bool pass() const;
  // One line: "0.0% of 3600 px rejected (Šidák level 2.8e-06 per test); bias -3.02% [-3.21%, -2.83%] over the
  // frame, ...; worst pixel 40,12: 0.61 against mean 0.70 [0.66, 0.74], t = -8.1".
  std::string describe() const;
};

}  // namespace mrr
