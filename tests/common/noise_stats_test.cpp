// The statistics of the noise-aware verdict (compare/metrics/noise_stats.h, compare/parity/noise.h):
// Student's t against closed forms, Šidák's formula, the coverage of the t interval on Gaussian
// data from a fixed RNG, and the image test on synthetic noisy frames with planted faults.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/tolerance.h"
#include "compare/parity/noise.h"
#include "compare/metrics/noise_stats.h"

namespace mrr {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(NoiseStats, StudentTMatchesClosedForms) {
  for (double t : {-30.0, -3.0, -0.5, 0.0, 0.7, 2.0, 12.0, 1e4}) {
    // df = 1 is Cauchy's: 1/2 + atan(t)/π; df = 2: 1/2 + t / (2 sqrt(2 + t²)).
    EXPECT_NEAR(studentTCdf(t, 1.0), 0.5 + std::atan(t) / kPi, 1e-12) << t;
    EXPECT_NEAR(studentTCdf(t, 2.0), 0.5 + t / (2.0 * std::sqrt(2.0 + t * t)), 1e-12) << t;
  }
  // Far tails, relative: df = 1, P(|T| ≥ t) = 1 − 2 atan(t)/π = 2 atan(1/t)/π.
  EXPECT_NEAR(studentTTwoSided(1e5, 1.0) / (2.0 * std::atan(1e-5) / kPi), 1.0, 1e-9);
  // Large df tends to the normal: P(|Z| ≥ 1.959963985) = 0.05.
  EXPECT_NEAR(studentTTwoSided(1.959963985, 1e7), 0.05, 1e-6);
  // Tabulated critical values (two-sided): t(0.05, 10) = 2.228138852, t(0.01, 15) = 2.946712883.
  EXPECT_NEAR(studentTCritical(0.05, 10.0), 2.228138852, 1e-8);
  EXPECT_NEAR(studentTCritical(0.01, 15.0), 2.946712883, 1e-8);
  EXPECT_NEAR(studentTTwoSided(studentTCritical(1e-7, 15.0), 15.0), 1e-7, 1e-13);
}

TEST(NoiseStats, SidakLevel) {
  EXPECT_DOUBLE_EQ(sidakLevel(0.01, 1), 0.01);
  EXPECT_NEAR(sidakLevel(0.05, 2), 1.0 - std::sqrt(0.95), 1e-15);
  // The family-wise rate is back at α: 1 − (1 − a)^m = α.
  const double a = sidakLevel(0.01, 1000000);
  EXPECT_NEAR(-std::expm1(1000000.0 * std::log1p(-a)), 0.01, 1e-12);
  EXPECT_GT(a, 0.01 / 1e6);  // a little above Bonferroni's
  EXPECT_LT(a, 1.01 * 0.01 / 1e6);
}

TEST(NoiseStats, WelchTestByHand) {
  // Means 10 and 8, variances of the means 0.5 and 0.25, df 9 and 4:
  // t = 2 / sqrt(0.75), ν = 0.75² / (0.25/9 + 0.0625/4).
  const WelchResult w = welchTest(10.0, 0.5, 9.0, 8.0, 0.25, 4.0);
  EXPECT_NEAR(w.t, 2.0 / std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(w.df, 0.5625 / (0.25 / 9.0 + 0.0625 / 4.0), 1e-12);
  EXPECT_NEAR(w.p, studentTTwoSided(w.t, w.df), 1e-15);
  // No spread: equal means pass, others are rejected.
  EXPECT_EQ(welchTest(1.0, 0.0, 3.0, 1.0, 0.0, 3.0).p, 1.0);
  EXPECT_EQ(welchTest(1.0, 0.0, 3.0, 0.9, 0.0, 3.0).p, 0.0);
}

TEST(NoiseStats, MeanIntervalCoversAtItsLevelOnGaussianData) {
  std::mt19937 rng(40);
  std::normal_distribution<double> normal(3.0, 2.0);
  int covered = 0;
  const int trials = 4000;
  for (int i = 0; i < trials; ++i) {
    std::vector<double> v(8);
    for (double& x : v) x = normal(rng);
    const MeanInterval m = meanInterval(v, 0.95);
    covered += m.lo <= 3.0 && 3.0 <= m.hi;
  }
  // Binomial(4000, 0.95): σ = 0.0034; 4σ either side.
  EXPECT_NEAR(static_cast<double>(covered) / trials, 0.95, 0.014);
}

// A synthetic stochastic stage: each pixel a mean of `n` uniform samples around a smooth field,
// drawn anew per seed.
ImageF noisyFrame(std::mt19937& rng, int w, int h, int n, double scale = 1.0) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ImageF image(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double truth = 0.3 + 0.5 * (x + y) / static_cast<double>(w + h);
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += u(rng) < truth ? 1.0 : 0.0;
      image.at(x, y) = static_cast<float>(scale * sum / n);
    }
  return image;
}

struct Synthetic {
  std::vector<ImageF> seeds;
  std::vector<char> all;
  std::vector<NoiseRegion> regions;
};

Synthetic synthetic(std::mt19937& rng, int w, int h, int n) {
  Synthetic s;
  for (int k = 0; k < kNoiseRule.seeds; ++k) s.seeds.push_back(noisyFrame(rng, w, h, n));
  s.all.assign(static_cast<size_t>(w) * h, 1);
  std::vector<char> left(s.all.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w / 4; ++x) left[static_cast<size_t>(y) * w + x] = 1;
  s.regions = {{"the frame", s.all}, {"the left quarter", left}};
  return s;
}

TEST(NoiseImageTest, AnotherDrawPassesAndAShiftOrALocalBugFails) {
  std::mt19937 rng(4040);
  const int w = 96, h = 64, n = 64;
  const Synthetic s = synthetic(rng, w, h, n);
  // Another draw of the same estimator passes, on several draws.
  for (int i = 0; i < 5; ++i) {
    const NoiseFigures f = noiseTest(noisyFrame(rng, w, h, n), s.seeds, s.all, s.regions, n);
    EXPECT_TRUE(f.pass()) << f.describe();
    EXPECT_EQ(f.rejected, 0) << f.describe();
  }
  // 3% too dark: no pixel shows it, the bias does (over the frame, its interval excludes 0).
  const NoiseFigures dark = noiseTest(noisyFrame(rng, w, h, n, 0.97), s.seeds, s.all, s.regions, n);
  EXPECT_FALSE(dark.pass()) << dark.describe();
  EXPECT_EQ(dark.rejected, 0) << dark.describe();
  ASSERT_FALSE(dark.biases.empty());
  EXPECT_FALSE(dark.biases[0].pass);
  EXPECT_LT(dark.biases[0].hi, 0.0);
  EXPECT_NEAR(dark.biases[0].bias, -0.03, 0.01) << dark.describe();
  // A local bug: a 4x4 patch at 0 is rejected per pixel, and named as the worst pixel.
  ImageF patch = noisyFrame(rng, w, h, n);
  for (int y = 30; y < 34; ++y)
    for (int x = 60; x < 64; ++x) patch.at(x, y) = 0.0f;
  const NoiseFigures local = noiseTest(patch, s.seeds, s.all, s.regions, n);
  EXPECT_FALSE(local.pass());
  EXPECT_GE(local.rejected, 8) << local.describe();
  EXPECT_LE(local.rejected, 16) << local.describe();
  EXPECT_GE(local.worstX, 60);
  EXPECT_LT(local.worstX, 64);
  EXPECT_GE(local.worstY, 30);
  EXPECT_LT(local.worstY, 34);
  EXPECT_LT(local.worstValue, local.worstLo);
}

// The false-alarm rate of the whole test on frames that are right: with the family-wise levels
// at 1% each, at most a few of 40 correct frames may fail.
TEST(NoiseImageTest, FalseAlarmsStayRare) {
  std::mt19937 rng(1234);
  const int w = 32, h = 24, n = 16;
  int failed = 0;
  for (int i = 0; i < 40; ++i) {
    const Synthetic s = synthetic(rng, w, h, n);
    failed += !noiseTest(noisyFrame(rng, w, h, n), s.seeds, s.all, s.regions, n).pass();
  }
  EXPECT_LE(failed, 3);
}

// Heavy-tailed samples, as SSGI's: each sample is worth 2 (a lit surface reached) with
// probability 0.9 in a bright patch and 0.002 elsewhere, else 0. Most dark pixels see no hit in
// any of the K seeds; another draw that hits there once (2/N) is no bug: one sample is worth as
// much as the stage's brightest pixel (docs/spec.md §8), not the dark pixel's seeds or the stage's
// mean. A blow-up patch is still rejected.
ImageF heavyTailedFrame(std::mt19937& rng, int w, int h, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ImageF image(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double hit = x < 4 && y < 8 ? 0.9 : 0.002;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += u(rng) < hit ? 2.0 : 0.0;
      image.at(x, y) = static_cast<float>(sum / n);
    }
  return image;
}

TEST(NoiseImageTest, HeavyTailedSamplesAreNoBug) {
  std::mt19937 rng(77);
  const int w = 32, h = 24, n = 8;
  std::vector<ImageF> seeds;
  for (int k = 0; k < kNoiseRule.seeds; ++k) seeds.push_back(heavyTailedFrame(rng, w, h, n));
  const std::vector<char> all(static_cast<size_t>(w) * h, 1);
  int rareHits = 0, passed = 0;
  for (int draw = 0; draw < 5; ++draw) {
    const ImageF subject = heavyTailedFrame(rng, w, h, n);
    for (size_t i = 0; i < subject.data.size(); ++i) {
      bool seedsDark = true;
      for (const ImageF& seed : seeds) seedsDark = seedsDark && seed.data[i] == 0.0f;
      rareHits += seedsDark && subject.data[i] > 0.0f;  // what the pixel's own seeds never showed
    }
    const NoiseFigures f = noiseTest(subject, seeds, all, {{"the frame", all}}, n);
    EXPECT_EQ(f.rejected, 0) << f.describe();
    passed += f.rejected == 0;
  }
  EXPECT_GE(rareHits, 10);  // the case is exercised: without the stage-wide sample scale these are rejected
  EXPECT_EQ(passed, 5);
  ImageF blowUp = heavyTailedFrame(rng, w, h, n);
  for (int y = 12; y < 14; ++y)
    for (int x = 20; x < 22; ++x) blowUp.at(x, y) = 8.0f;
  const NoiseFigures bad = noiseTest(blowUp, seeds, all, {{"the frame", all}}, n);
  EXPECT_GE(bad.rejected, 4) << bad.describe();
  EXPECT_FALSE(bad.pass());
}

}  // namespace
}  // namespace mrr
