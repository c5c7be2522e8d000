// Host-made constants both paths share (SPEC §3, §7): Gaussian weights, SSAO kernel, hash.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "common/hash.h"
#include "common/kernels.h"
#include "common/params.h"

namespace mrr {
namespace {

// Discrete sampling of a Gaussian at integer offsets, truncated at 3σ: its variance is
// within 1% of σ² for the paper's σ² (0.924 .. 3.696).
constexpr double kDiscreteVarianceTolerance = 0.01;

TEST(Kernels, GaussianWeightsSumToOne) {
  for (float sigma2 : {0.924f, 1.848f, 3.696f, 10.0f}) {
    const auto w = gaussianWeights(sigma2);
    EXPECT_EQ(static_cast<int>(w.size()), 2 * gaussianRadius(sigma2) + 1);
    EXPECT_NEAR(std::accumulate(w.begin(), w.end(), 0.0), 1.0, 1e-6);
    for (size_t i = 0; i < w.size(); ++i) EXPECT_FLOAT_EQ(w[i], w[w.size() - 1 - i]);  // symmetric
  }
}

TEST(Kernels, BlurOfDeltaHasVarianceSigma2) {
  for (float sigma2 : {0.924f, 1.848f, 3.696f}) {
    const auto w = gaussianWeights(sigma2);
    const int r = gaussianRadius(sigma2);
    double var = 0.0;
    for (int i = -r; i <= r; ++i) var += w[static_cast<size_t>(i + r)] * i * i;
    EXPECT_NEAR(var / sigma2, 1.0, kDiscreteVarianceTolerance) << "sigma2 " << sigma2;
  }
}

TEST(Kernels, ZeroVarianceIsNoBlur) {
  EXPECT_EQ(gaussianRadius(0.0f), 0);
  EXPECT_EQ(gaussianWeights(0.0f), std::vector<float>{1.0f});
}

TEST(Kernels, PaperRadii) {
  // r = ceil(3σ): σ² = 0.924 → 3, 1.848 → 5, 3.696 → 6.
  EXPECT_EQ(gaussianRadius(0.924f), 3);
  EXPECT_EQ(gaussianRadius(1.848f), 5);
  EXPECT_EQ(gaussianRadius(3.696f), 6);
}

TEST(Kernels, SsaoKernelInUnitHemisphereAndDeterministic) {
  const auto k = ssaoKernel(256);
  ASSERT_EQ(k.size(), 256u);
  for (const auto& v : k) {
    EXPECT_GE(v.z, 0.0f);
    EXPECT_LE(glm::length(v), 1.0f + 1e-6f);
    EXPECT_GT(glm::length(v), 0.0f);
  }
  EXPECT_EQ(ssaoKernel(256), k);
  // Denser near the centre: the first quarter is shorter on average than the last.
  double first = 0, last = 0;
  for (int i = 0; i < 64; ++i) {
    first += glm::length(k[static_cast<size_t>(i)]);
    last += glm::length(k[static_cast<size_t>(192 + i)]);
  }
  EXPECT_LT(first, 0.5 * last);
}

TEST(Hash, MatchesIndependentUint32Implementation) {
  // Values from a Python implementation of the same arithmetic masked to 32 bits, which is
  // what GLSL's uint does (wrap-around): a C++ change that relies on wider arithmetic fails.
  EXPECT_EQ(pcgHash(0u), 129708002u);
  EXPECT_EQ(pcgHash(1u), 2831084092u);
  EXPECT_EQ(pcgHash(2u), 2055130248u);
  EXPECT_EQ(pcgHash(12345u), 4099845390u);
  EXPECT_EQ(pcgHash(0xffffffffu), 3861530882u);
  EXPECT_EQ(pixelHash(3u, 5u, 2u), 2351279509u);
}

// --seed: seed 0 is mrr's own sampling, bit for bit; another seed another draw.
TEST(Seed, ZeroKeepsTheKernelsAndRotationsOthersMoveThem) {
  EXPECT_EQ(kernelSeed(kSsaoKernelSeed, 0), kSsaoKernelSeed);
  EXPECT_EQ(kernelSeed(kSsgiKernelSeed, 0), 0x51a61u);
  EXPECT_EQ(ssaoKernel(64, kernelSeed(kSsaoKernelSeed, 0)), ssaoKernel(64));
  EXPECT_NE(ssaoKernel(64, kernelSeed(kSsaoKernelSeed, 1)), ssaoKernel(64));
  EXPECT_NE(ssaoKernel(64, kernelSeed(kSsaoKernelSeed, 1)), ssaoKernel(64, kernelSeed(kSsaoKernelSeed, 2)));
  Settings s = defaultSettings(Effect::Ssao);
  EXPECT_EQ(makeConstants(s, 1.0f).ssao.kernel, ssaoKernel(s.ssao.samples));
  s.seed = 3;
  EXPECT_EQ(makeConstants(s, 1.0f).ssao.seed, 3u);
  EXPECT_EQ(makeConstants(s, 1.0f).ssgi.kernel, ssaoKernel(s.ssgi.samples, kSsgiKernelSeed + 3u * 0x9e3779b9u));
  // Rotations: seed 0 is pixelHash; test vectors of rotationHash for the docs and foreign renderers.
  for (uint32_t level = 0; level < 4; ++level) EXPECT_EQ(rotationHash(3u, 5u, level, 0u), pixelHash(3u, 5u, level));
  EXPECT_EQ(rotationHash(3u, 5u, 2u, 1u), pixelHash(3u, 5u, 6u));
  EXPECT_NE(rotationHash(3u, 5u, 2u, 1u), rotationHash(3u, 5u, 2u, 0u));
}

TEST(Hash, UnitIsInHalfOpenRange) {
  EXPECT_EQ(hashToUnit(0u), 0.0f);
  EXPECT_LT(hashToUnit(0xffffffffu), 1.0f);
}

TEST(Params, LevelGeometryNests) {
  Settings s = defaultSettings(Effect::Ssao);
  s.width = 1279;
  s.height = 719;
  const Constants c = makeConstants(s, 10.0f);
  EXPECT_EQ(c.paddedWidth, 1280);
  EXPECT_EQ(c.paddedHeight, 720);
  for (int l = 0; l < kLevelCount; ++l) {
    EXPECT_EQ(c.levels[static_cast<size_t>(l)].width * (1 << l), c.paddedWidth);
    EXPECT_EQ(c.levels[static_cast<size_t>(l)].height * (1 << l), c.paddedHeight);
  }
}

TEST(Params, TableOneDefaults) {
  const Settings s = defaultSettings(Effect::Ssao);
  EXPECT_FLOAT_EQ(s.levels[0].sigma2, 0.924f);
  EXPECT_FLOAT_EQ(s.levels[0].weight, 100.0f);
  EXPECT_FLOAT_EQ(s.levels[1].sigma2, 1.848f);
  EXPECT_FLOAT_EQ(s.levels[1].weight, 50.0f);
  EXPECT_FLOAT_EQ(s.levels[2].sigma2, 3.696f);
  EXPECT_FLOAT_EQ(s.levels[2].weight, 20.0f);
  EXPECT_FLOAT_EQ(s.levels[3].weight, 1.0f);
}

TEST(Params, FullModeEnablesOnlyLevelZero) {
  Settings s = defaultSettings(Effect::Ssao);
  s.mode = Mode::Full;
  const Constants c = makeConstants(s, 1.0f);
  EXPECT_TRUE(c.levels[0].enabled);
  for (int l = 1; l < kLevelCount; ++l) EXPECT_FALSE(c.levels[static_cast<size_t>(l)].enabled);
  EXPECT_EQ(c.coarsestEnabled, 0);
}

}  // namespace
}  // namespace mrr
