// LDR-FLIP (compare/metrics/flip.h): analytic cases, then agreement with the reference implementation
// on synthetic pairs and on mrr's own frames.
//
// How the reference figures were produced: NVlabs/flip at commit 1eb247c (v1.6; its C++ tool
// src/cpp/tool/FLIP-tool.cpp built with `g++ -O3 -fopenmp -std=c++17`), run as
//   MRR_FLIP_PAIRS_DIR=/tmp/pairs build/tests/common_tests --gtest_filter='Flip.*'
//   flip -r /tmp/pairs/NAME-ref.png -t /tmp/pairs/NAME-test.png
// which prints "Mean: ..." (at its default 67.02 pixels per degree, this file's default too).
// The pairs are 8-bit (every value k/255), so the PNG the tool reads holds exactly the values
// this test passes to mrr::flip.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/image_io.h"
#include "compare/metrics/flip.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

// The issue asks for max(1e-3, 1%); measured, every pair agrees within 0.15% (or 7e-6 where
// the mean is near 0: the reference gives 7e-6 for identical images, this code exactly 0),
// so the test holds a tighter bound, max(1e-5, 0.5%), to catch a drift the would not.
double allowedDifference(double referenceMean) { return std::max(1e-5, 0.005 * referenceMean); }

float quantise(float v) { return std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f; }

ImageF quantised(ImageF img) {
  for (float& v : img.data) v = quantise(v);
  return img;
}

// A deterministic generator (64-bit LCG): the same pairs on every machine.
struct Lcg {
  uint64_t state;
  float next() {  // [0,1)
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<float>(state >> 40) / static_cast<float>(1ull << 24);
  }
};

constexpr int kW = 256, kH = 192;

// A colour picture with smooth ramps, discs and stripes: something with edges, points and
// flat parts.
ImageF basePicture() {
  ImageF img(kW, kH, 3);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float u = static_cast<float>(x) / (kW - 1), v = static_cast<float>(y) / (kH - 1);
      float r = 0.2f + 0.6f * u, g = 0.3f + 0.5f * v, b = 0.5f + 0.3f * std::sin(6.0f * u);
      const float dx = static_cast<float>(x - 80), dy = static_cast<float>(y - 90);
      if (dx * dx + dy * dy < 40.0f * 40.0f) r = 0.9f, g = 0.2f, b = 0.1f;
      const float ex = static_cast<float>(x - 190), ey = static_cast<float>(y - 60);
      if (ex * ex + ey * ey < 25.0f * 25.0f) r = 0.1f, g = 0.2f, b = 0.8f;
      if (y > 150 && (x / 4) % 2 == 0) r = g = b = 0.95f;
      img.at(x, y, 0) = r;
      img.at(x, y, 1) = g;
      img.at(x, y, 2) = b;
    }
  return quantised(img);
}

ImageF greyRamp() {  // an AO-like grey picture: a ramp with a dark contact band
  ImageF img(kW, kH, 1);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      img.at(x, y) = 0.35f + 0.6f * static_cast<float>(x) / (kW - 1) - (std::abs(y - 100) < 6 ? 0.3f : 0.0f);
  return quantised(img);
}

struct Pair {
  std::string name;
  ImageF reference, test;
  double referenceMean;  // the reference implementation's mean FLIP (see the top of the file)
};

std::vector<Pair> syntheticPairs() {
  const ImageF base = basePicture();
  std::vector<Pair> pairs;
  {  // uniform noise of ±0.1 on every channel
    ImageF t = base;
    Lcg rng{12345};
    for (float& v : t.data) v += 0.2f * (rng.next() - 0.5f);
    pairs.push_back({"noise", base, quantised(t), 0.0});
  }
  {  // a vertical edge moved by two pixels
    ImageF r(kW, kH, 3), t(kW, kH, 3);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        for (int c = 0; c < 3; ++c) {
          r.at(x, y, c) = x < 128 ? 0.1f : 0.8f;
          t.at(x, y, c) = x < 130 ? 0.1f : 0.8f;
        }
    pairs.push_back({"shifted-edge", quantised(r), quantised(t), 0.0});
  }
  {  // a 5×5 box blur
    ImageF t = base;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x)
        for (int c = 0; c < 3; ++c) {
          float s = 0.0f;
          for (int j = -2; j <= 2; ++j)
            for (int i = -2; i <= 2; ++i)
              s += base.at(std::clamp(x + i, 0, kW - 1), std::clamp(y + j, 0, kH - 1), c);
          t.at(x, y, c) = s / 25.0f;
        }
    pairs.push_back({"blur", base, quantised(t), 0.0});
  }
  {  // a colour shift: more red, less blue
    ImageF t = base;
    for (size_t p = 0; p < t.pixelCount(); ++p) {
      t.data[3 * p] += 0.1f;
      t.data[3 * p + 2] -= 0.08f;
    }
    pairs.push_back({"colour-shift", base, quantised(t), 0.0});
  }
  {  // darker by a fifth
    ImageF t = base;
    for (float& v : t.data) v *= 0.8f;
    pairs.push_back({"darker", base, quantised(t), 0.0});
  }
  {  // a fine checkerboard against its mean grey
    ImageF r(kW, kH, 1), t(kW, kH, 1, 0.5f);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) r.at(x, y) = ((x + y) % 2) ? 0.25f : 0.75f;
    pairs.push_back({"checker-grey", quantised(r), quantised(t), 0.0});
  }
  {  // a grey picture at a quarter of the resolution, blown up blockily: what a reduced rate
     // gets wrong
    const ImageF r = greyRamp();
    ImageF t = r;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) t.at(x, y) = r.at(x / 4 * 4, y / 4 * 4);
    pairs.push_back({"grey-blocky", r, t, 0.0});
  }
  {  // identical
    pairs.push_back({"identical", base, base, 0.0});
  }
  // The reference implementation's means, in the order above.
  const double means[] = {0.122315, 0.016532, 0.104295, 0.318442, 0.476706, 0.222396, 0.048982, 0.000007};
  for (size_t i = 0; i < pairs.size(); ++i) pairs[i].referenceMean = means[i];
  return pairs;
}

// mrr's own frames: builtin:demo at 192x108, each effect's final buffer (shown as grey, as
// `render --out x.png` shows it) and the SSAO frame's shaded image (sRGB-encoded, as
// `--shaded x.png`), method mrr against full. (SSM's frame is the same at this size, mrr
// against full: FLIP 0 here, 1e-6 in the reference.)
std::vector<Pair> framePairs() {
  std::vector<Pair> pairs;
  for (Effect effect : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
    Settings s = defaultSettings(effect);
    s.width = 192;
    s.height = 108;
    s.setSamples(16);
    s.neverSlower = false;  // the method itself, not its fall-back to full
    s.mode = Mode::Mrr;
    // The radii the reference tool's frames were rendered with (before the view-framed default).
    const float diagonal = makeBuiltinScene("demo").bounds().diagonal();
    s.ssao.radius = SsaoSettings::kDiagonalFractionBefore * diagonal;
    s.ssao.biasFraction = SsaoSettings::kBiasFractionBefore;
    s.ssgi.radius = SsgiSettings::kDiagonalFractionBefore * diagonal;
    const test::Rendered mrr = test::renderScene("builtin:demo", s);
    s.mode = Mode::Full;
    const test::Rendered full = test::renderScene("builtin:demo", s);
    const std::string name = "demo-" + toString(effect);
    pairs.push_back({name + "-effect", quantised(full.frame.final()), quantised(mrr.frame.final()), 0.0});
    if (effect == Effect::Ssao)
      pairs.push_back({name + "-shaded", quantised(linearToDisplay(full.frame.shaded)),
                       quantised(linearToDisplay(mrr.frame.shaded)), 0.0});
  }
  const double means[] = {0.004404, 0.004550, 0.000001, 0.002110};
  for (size_t i = 0; i < pairs.size(); ++i) pairs[i].referenceMean = means[i];
  return pairs;
}

// Writes the pairs for the reference tool when MRR_FLIP_PAIRS_DIR names a folder.
void writePairsFor(const std::vector<Pair>& pairs) {
  const char* dir = std::getenv("MRR_FLIP_PAIRS_DIR");
  if (!dir || !*dir) return;
  for (const Pair& p : pairs) {
    writeImage(std::string(dir) + "/" + p.name + "-ref.png", p.reference);
    writeImage(std::string(dir) + "/" + p.name + "-test.png", p.test);
  }
}

TEST(Flip, IdenticalImagesGiveExactlyZero) {
  for (const ImageF& img : {basePicture(), greyRamp()}) {
    const FlipResult f = flip(img, img);
    for (float v : f.errorMap.data) ASSERT_EQ(v, 0.0f);
    EXPECT_EQ(f.stats.mean, 0.0);
    EXPECT_EQ(f.stats.max, 0.0);
  }
}

// Every step treats the two images alike and compares them by absolute differences (HyAB's
// |ΔL| and Euclidean chroma, the features' | |e_r| − |e_t| |), so LDR-FLIP is symmetric: the
// paper's asymmetry is HDR-FLIP's, whose exposures come from the reference alone.
TEST(Flip, MapIsSymmetric) {
  for (const Pair& p : syntheticPairs()) {
    const FlipResult ab = flip(p.reference, p.test), ba = flip(p.test, p.reference);
    ASSERT_EQ(ab.errorMap.data, ba.errorMap.data) << p.name;
  }
}

TEST(Flip, ErrorsLieInZeroToOne) {
  for (const Pair& p : syntheticPairs()) {
    const FlipResult f = flip(p.reference, p.test);
    for (float v : f.errorMap.data) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << p.name << ": " << v;
    EXPECT_LE(f.stats.q1, f.stats.median);
    EXPECT_LE(f.stats.median, f.stats.q3);
    EXPECT_LE(f.stats.q3, f.stats.max);
  }
}

// Flat black against flat white, by hand: no features, so FLIP is the colour term alone.
// HyAB(black, white) = ΔL* = 100, compressed 100^0.7 = 25.12. cmax: green (L* 87.74, Hunt-
// scaled a*, b* −75.61, 72.98) against blue (32.30, 25.58, −34.84) is 55.44 + 147.86 =
// 203.30, compressed 41.28, and pc·cmax = 16.51. 25.12 is above it, so the error is
// 0.95 + (25.12 − 16.51) / (41.28 − 16.51) · 0.05 = 0.9674 at every pixel.
TEST(Flip, BlackAgainstWhiteByHand) {
  constexpr double kByHand = 0.9674, kRounding = 5e-4;  // the hand figures' four digits
  const FlipResult f = flip(ImageF(32, 32, 3, 0.0f), ImageF(32, 32, 3, 1.0f));
  EXPECT_NEAR(f.stats.mean, kByHand, kRounding);
  EXPECT_EQ(f.stats.max, f.stats.q1);  // flat
}

TEST(Flip, SameForAnyThreadCount) {
  const std::vector<Pair> pairs = syntheticPairs();
  const Pair& p = pairs[2];
  PixelVector<float> first;
  for (size_t threads : {1, 2, 8}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    const FlipResult f = flip(p.reference, p.test);
    if (first.empty()) first = f.errorMap.data;
    ASSERT_EQ(f.errorMap.data, first) << threads << " threads";
  }
}

TEST(Flip, DifferentSizesAreAnError) {
  EXPECT_THROW(flip(ImageF(8, 8, 3), ImageF(8, 9, 3)), MrrError);
}

TEST(Flip, StatsOfAKnownMap) {
  ImageF m(4, 1, 1);
  m.data = {0.1f, 0.4f, 0.2f, 0.3f};  // sorted 0.1 0.2 0.3 0.4: q at 0.75, 1.5, 2.25
  const FlipStats s = flipStats(m);
  EXPECT_NEAR(s.mean, 0.25, 1e-7);
  EXPECT_NEAR(s.q1, 0.175, 1e-7);
  EXPECT_NEAR(s.median, 0.25, 1e-7);
  EXPECT_NEAR(s.q3, 0.325, 1e-7);
  EXPECT_NEAR(s.max, 0.4, 1e-7);
}

TEST(Flip, AgreesWithTheReferenceOnSyntheticPairs) {
  const std::vector<Pair> pairs = syntheticPairs();
  writePairsFor(pairs);
  for (const Pair& p : pairs) {
    const FlipResult f = flip(p.reference, p.test);
    EXPECT_NEAR(f.stats.mean, p.referenceMean, allowedDifference(p.referenceMean)) << p.name;
  }
}

// Other viewing conditions: the reference tool with -ppd 30 and -ppd 120 (as above).
TEST(Flip, AgreesWithTheReferenceAtOtherViewingConditions) {
  const std::vector<Pair> pairs = syntheticPairs();
  EXPECT_NEAR(flip(pairs[0].reference, pairs[0].test, 30.0).stats.mean, 0.241757, allowedDifference(0.241757));  // noise
  EXPECT_NEAR(flip(pairs[2].reference, pairs[2].test, 120.0).stats.mean, 0.079050, allowedDifference(0.079050));  // blur
}

TEST(Flip, AgreesWithTheReferenceOnMrrFrames) {
  const std::vector<Pair> pairs = framePairs();
  writePairsFor(pairs);
  for (const Pair& p : pairs) {
    const FlipResult f = flip(p.reference, p.test);
    EXPECT_NEAR(f.stats.mean, p.referenceMean, allowedDifference(p.referenceMean)) << p.name;
  }
}

}  // namespace
}  // namespace mrr
