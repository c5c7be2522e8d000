// The peers (SPEC §9) and the never-slower rule (SPEC §11) on the oracle: analytic cases,
// invariants, and the rule's decision both ways.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "common/error.h"
#include "compare/report/report.h"
#include "compare/rule/rule.h"
#include "cpu_ref/peers.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

using test::renderScene;
using test::ssaoSettings;

Settings method(Settings s, Mode m) {
  s.mode = m;
  return s;
}

TEST(TileRates, EdgeTileIsOneByOneItsNeighboursTwoByTwoTheRestFourByFour) {
  ImageU8 e(80, 64);     // 5×4 tiles
  e.at(37, 20) = 1;      // tile (2, 1)
  const ImageU8 r = tileRates(e);
  ASSERT_EQ(r.width, 5);
  ASSERT_EQ(r.height, 4);
  for (int ty = 0; ty < 4; ++ty)
    for (int tx = 0; tx < 5; ++tx) {
      const int expected = tx == 2 && ty == 1 ? 0 : (std::abs(tx - 2) <= 1 && std::abs(ty - 1) <= 1 ? 1 : 2);
      EXPECT_EQ(r.at(tx, ty), expected) << "tile " << tx << "," << ty;
    }
}

TEST(TileRates, PartialTilesAtThePaddedBorderCount) {
  ImageU8 e(40, 24);  // 3×2 tiles, the last column and row partial
  e.at(39, 23) = 1;
  const ImageU8 r = tileRates(e);
  ASSERT_EQ(r.width, 3);
  ASSERT_EQ(r.height, 2);
  EXPECT_EQ(r.at(2, 1), 0);
  EXPECT_EQ(r.at(0, 0), 2);
  EXPECT_EQ(r.at(1, 0), 1);
}

TEST(JointBilateral, WeightFollowsTheFormula) {
  Constants::Bilateral b;
  b.sigmaDepth = 0.05f;
  b.normalPower = 16.0f;
  const glm::vec3 n(0, 0, 1), tilted(0, std::sin(0.3f), std::cos(0.3f)), side(1, 0, 0);
  EXPECT_FLOAT_EQ(jointBilateralWeight(0.25f, true, 2.0f, n, true, 2.0f, n, b), 0.25f);
  // one σ_z·z_p of depth apart: e^{−1}
  EXPECT_NEAR(jointBilateralWeight(0.25f, true, 2.0f, n, true, 2.1f, n, b), 0.25f * std::exp(-1.0f), 1e-6f);
  EXPECT_NEAR(jointBilateralWeight(1.0f, true, 2.0f, n, true, 2.0f, tilted, b), std::pow(std::cos(0.3f), 16.0f), 1e-6f);
  EXPECT_EQ(jointBilateralWeight(1.0f, true, 2.0f, n, true, 2.0f, side, b), 0.0f);    // perpendicular
  EXPECT_EQ(jointBilateralWeight(1.0f, true, 2.0f, n, false, 0.0f, n, b), 0.0f);     // geometry vs background
  EXPECT_EQ(jointBilateralWeight(1.0f, false, 0.0f, n, true, 2.0f, n, b), 0.0f);
  EXPECT_FLOAT_EQ(jointBilateralWeight(0.5f, false, 0.0f, n, false, 0.0f, n, b), 0.5f);  // both background
}

TEST(JointBilateral, AllWeightsVanishingTakesTheNearestTap) {
  Settings s = ssaoSettings(16, 16, 4, Mode::Uniform1);
  const Constants c = makeConstants(s, 1.0f);
  const LevelConstants& l1 = c.levels[1];
  GBuffer full(16, 16), coarse(8, 8);
  ImageF sub(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      sub.at(x, y) = static_cast<float>(10 * y + x);
      coarse.hit.at(x, y) = 1;  // coarse is all geometry, p is background: every weight is 0
      coarse.depth.at(x, y) = 1.0f;
    }
  float v = -1.0f;
  jointBilateralAt(sub, coarse, full, l1, c.bilateral, 5, 9, &v);  // u = (2.25, 4.25): nearest (2, 4)
  EXPECT_EQ(v, 42.0f);
}

TEST(Peers, OpenPlaneIsUnoccludedForEveryMethod) {
  for (const MethodInfo& row : methods()) {  // every row of the method table
    const Mode m = row.mode;
    SCOPED_TRACE(toString(m));
    const auto r = renderScene("builtin:plane", method(ssaoSettings(64, 48, 16), m));
    for (float v : r.frame.final().data) ASSERT_NEAR(v, 1.0f, 1e-6f);
  }
}

TEST(Peers, TilesWithoutEdgesShadeEverythingAtFourByFour) {
  const auto r = renderScene("builtin:plane", method(ssaoSettings(64, 48, 16), Mode::Tiles));
  for (uint8_t rate : r.frame.tileRates.data) EXPECT_EQ(rate, 2);
  EXPECT_EQ(r.frame.levels[0].shadedPixels, 0);
  EXPECT_EQ(r.frame.levels[1].shadedPixels, 0);
  EXPECT_EQ(r.frame.levels[2].shadedPixels, 16 * 12);
  EXPECT_DOUBLE_EQ(r.frame.idealSpeedup, 16.0);
}

TEST(Peers, UniformShadesEveryPixelOfItsLevelAndNothingAtFullRes) {
  for (auto [m, k] : {std::pair{Mode::Uniform1, 1}, std::pair{Mode::Uniform2, 2}}) {
    const auto r = renderScene("builtin:demo", method(ssaoSettings(61, 37, 8), m));
    const int s = 1 << k, w = (61 + s - 1) / s, h = (37 + s - 1) / s;
    EXPECT_EQ(r.frame.levels[0].shadedPixels, 0);
    EXPECT_EQ(r.frame.levels[static_cast<size_t>(k)].shadedPixels, w * h);
    EXPECT_EQ(r.frame.shadedPixelsTotal, w * h);
    EXPECT_FALSE(r.frame.levels[0].gbuffer.depth.empty()) << "the full-res G-buffer guides the upsampling";
  }
}

TEST(Peers, TilesBroadcastTheirLevelsValueUnfiltered) {
  const auto r = renderScene("builtin:demo", method(ssaoSettings(250, 150, 4), Mode::Tiles));
  const FrameResult& f = r.frame;
  int perRate[3] = {0, 0, 0};
  for (int y = 0; y < 150; ++y)
    for (int x = 0; x < 250; ++x) {
      const int l = f.tileRates.at(x / kTileSize, y / kTileSize);
      ++perRate[l];
      const LevelResult& lr = f.levels[static_cast<size_t>(l)];
      ASSERT_EQ(lr.masks.stencil.at(x >> l, y >> l), 1) << "dead pixel " << x << "," << y;
      ASSERT_EQ(f.final().at(x, y), lr.sub.at(x >> l, y >> l));
      ASSERT_EQ(f.blend.levelMap.at(x, y), l);
    }
  for (int n : perRate) EXPECT_GT(n, 0) << "the demo has tiles of every rate";
}

TEST(Peers, SameBitsForOneAndTwoThreads) {
  for (Mode m : {Mode::Uniform1, Mode::Uniform2, Mode::Tiles})
    for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
      SCOPED_TRACE(toString(m) + " " + toString(e));
      Settings s = defaultSettings(e);
      s.width = 67;
      s.height = 45;
      s.setSamples(e == Effect::Ssm ? 16 : 8);
      s.mode = m;
      FrameResult one, two;
      {
        tbb::global_control g(tbb::global_control::max_allowed_parallelism, 1);
        one = renderScene("builtin:demo", s).frame;
      }
      {
        tbb::global_control g(tbb::global_control::max_allowed_parallelism, 2);
        two = renderScene("builtin:demo", s).frame;
      }
      ASSERT_EQ(one.final().data, two.final().data);
    }
}

TEST(Peers, ErrorAgainstFullIsFiniteAndOrdered) {
  // On the demo, SSAO: uniform-2 shades 1/16 of the pixels and must be the least accurate;
  // every method's error is finite and only full's is zero.
  Settings s = ssaoSettings(160, 96, 16);
  const auto full = renderScene("builtin:demo", method(s, Mode::Full));
  std::vector<double> rms(methods().size(), 0.0);
  for (const MethodInfo& row : methods()) {  // every row of the method table
    const Mode m = row.mode;
    const auto r = renderScene("builtin:demo", method(s, m));
    double sum = 0;
    for (size_t i = 0; i < r.frame.final().data.size(); ++i) {
      const double d = r.frame.final().data[i] - full.frame.final().data[i];
      sum += d * d;
    }
    rms[static_cast<size_t>(m)] = std::sqrt(sum / static_cast<double>(r.frame.final().data.size()));
    ASSERT_TRUE(std::isfinite(rms[static_cast<size_t>(m)]));
    // Only the reference is exact; every other row shades fewer pixels somewhere.
    if (row.reference) EXPECT_EQ(rms[static_cast<size_t>(m)], 0.0) << row.name;
    else EXPECT_GT(rms[static_cast<size_t>(m)], 0.0) << row.name;
  }
  EXPECT_GT(rms[static_cast<size_t>(Mode::Uniform2)], rms[static_cast<size_t>(Mode::Uniform1)]);
  EXPECT_GT(rms[static_cast<size_t>(Mode::Uniform2)], rms[static_cast<size_t>(Mode::Mrr)]);
}

// SPEC §11: the decision, both ways, and a fallen-back frame is the full frame bit for bit.
TEST(NeverSlower, FallsBackWhenTheOverheadEatsTheGainAndNotOtherwise) {
  SceneRequest req;
  req.scene = "builtin:demo";
  const ResolvedScene rs = resolveScene(req);
  const Renderer renderer(rs.scene);
  Settings s = ssaoSettings(96, 64, 8);
  s.neverSlower = true;
  const Constants c = makeConstants(s, rs.framed.size);
  const FrameResult full = renderer.render(rs.camera, makeConstants(method(s, Mode::Full), rs.framed.size));

  // The coarse G-buffers dearer than shading every pixel: the least the method could pay is
  // already no gain, so it falls back before its edges.
  CostModel costly = CostModel::defaults("cpu");
  costly.nsPerCoarseGbufferPixel = 1e6;
  const FrameResult early = renderer.render(rs.camera, c, {true, {}, &costly});
  EXPECT_TRUE(early.fallback.evaluated);
  EXPECT_TRUE(early.fallback.fellBack);
  EXPECT_TRUE(early.fallback.early);
  EXPECT_GT(early.fallback.predictedMrrMs, early.fallback.predictedFullMs);
  EXPECT_EQ(early.final().data, full.final().data) << "a fallen-back frame is the full frame";
  EXPECT_DOUBLE_EQ(early.idealSpeedup, 1.0);
  EXPECT_TRUE(early.edges.combined.empty()) << "no edges were found";
  EXPECT_EQ(early.timing("edges"), 0.0);
  // The floor needs no edge sample, and it decided: the sample was not taken. Asked for it
  // anyway (as the sweep and the calibration ask), the rule decides the same, on the same figures.
  EXPECT_TRUE(early.fallback.onFloor);
  EXPECT_TRUE(early.edgeSample.empty()) << "the floor ruled the method out before the edge sample";
  EXPECT_EQ(early.counts.edgeBlocks, 0);
  EXPECT_EQ(early.counts.reach, (std::array<int64_t, kLevelCount>{}));
  const FrameResult sampled = renderer.render(rs.camera, c, {true, {}, &costly, true});
  EXPECT_FALSE(sampled.edgeSample.empty());
  EXPECT_GT(sampled.counts.edgeBlocks, 0);
  EXPECT_TRUE(sampled.fallback.fellBack && sampled.fallback.onFloor);
  EXPECT_EQ(sampled.fallback.predictedMrrMs, early.fallback.predictedMrrMs);
  EXPECT_EQ(sampled.fallback.predictedFullMs, early.fallback.predictedFullMs);
  EXPECT_EQ(sampled.final().data, early.final().data);

  // Shading alone, and a stencilled pixel five times a dense one: the floor (the coarsest level
  // and the silhouettes) stays under full's, the method's stencils do not: it decides on the
  // stencils, late.
  CostModel free = CostModel::defaults("cpu");
  free.nsPerBlendPixel = free.nsPerFineBlendPixel = free.nsPerCoarseGbufferPixel = 0.0;
  free.nsPerEdgePixel = free.nsPerMaskPixel = free.edgesMasksFixedMs = 0.0;
  free.nsPerEdgeHitPixel = free.nsPerMaskReachPixel = 0.0;
  for (EffectCost& e : free.effect) {  // shading alone, at dense cost, nothing per frame
    e.sparseFactor = 1.0;
    e.fixedMs = 0.0;
  }
  free.stencilFill = {0.0, 0.0, 0.0};  // the edge sample's estimate no more than the silhouettes'
  CostModel sparse = free;
  for (EffectCost& e : sparse.effect) e.sparseFactor = 5.0;
  const FrameResult late = renderer.render(rs.camera, c, {true, {}, &sparse});
  EXPECT_TRUE(late.fallback.fellBack);
  EXPECT_FALSE(late.fallback.early);
  EXPECT_FALSE(late.fallback.onFloor);
  EXPECT_FALSE(late.edgeSample.empty()) << "past the floor, the rule takes the edge sample";
  EXPECT_EQ(late.final().data, full.final().data);
  EXPECT_FALSE(late.edges.combined.empty()) << "its edges are kept for debugging";

  const FrameResult kept = renderer.render(rs.camera, c, {true, {}, &free});
  EXPECT_FALSE(kept.fallback.fellBack);
  EXPECT_GT(kept.idealSpeedup, 1.2);
  EXPECT_NE(kept.final().data, full.final().data);

  s.neverSlower = false;
  const FrameResult off = renderer.render(rs.camera, makeConstants(s, rs.framed.size), {true, {}, &costly});
  EXPECT_FALSE(off.fallback.evaluated);
  EXPECT_GT(off.fallback.predictedMrrMs, off.fallback.predictedFullMs) << "predicted, not applied";
  EXPECT_GT(off.idealSpeedup, 1.2);

  // The rule's own work is the stage `rule` (SPEC §11's ρ), the method's alone: timed twice (its
  // counts, then the stencils'), with the rule on or off; once where it fell back early (no
  // stencils to count); never in full. The report gives a stage timed twice as the sum.
  auto ruleTimings = [](const FrameResult& f) {
    int n = 0;
    for (const StageTiming& t : f.timings) n += t.stage == "rule";
    return n;
  };
  EXPECT_EQ(ruleTimings(kept), 2);
  EXPECT_EQ(ruleTimings(late), 2);
  EXPECT_EQ(ruleTimings(off), 2);
  EXPECT_EQ(ruleTimings(early), 1);
  EXPECT_EQ(ruleTimings(full), 0);
  EXPECT_GT(kept.timing("rule"), 0.0);
  EXPECT_DOUBLE_EQ(makeReport(kept, RunInfo{}, std::nullopt)["timings_ms"]["rule"].get<double>(), kept.timing("rule"));
}

// SPEC §11's s_ℓ: a stencil over every paying pixel of level 0 is the dense frame, priced as
// full prices its shading whatever s; a stencil over none pays s; and a level's price rises with
// |S_ℓ| up to s = 2, the calibration's bound.
// SPEC §11's early estimate, fitted: frames whose stencils follow min(φ |R_ℓ|, η |Ê| (8/s_ℓ)²)
// exactly, sparse edges (the band binds) and crowded ones (the fill binds), give φ_ℓ and η_ℓ back
// within the grid's step; a level no frame shades keeps the model's.
TEST(NeverSlower, TheStencilFitFindsTheFillAndTheBandBack) {
  const std::array<double, 3> fill = {0.96, 0.8, 0.92}, band = {1.1, 2.5, 7.0};
  std::vector<CalibrationFrame> frames;
  for (const auto& [w, h] : {std::pair{320, 180}, std::pair{640, 360}, std::pair{1280, 720}})
    for (double edges : {0.02, 0.05, 0.1, 0.2, 0.4, 0.9, 1.0}) {  // the share of the frame's blocks marked
      const Constants c = makeConstants(ssaoSettings(w, h, 16), 1.0f);
      FrameCounts n;
      n.hitPixels = n.searchedPixels = static_cast<int64_t>(w) * h;
      n.edgeBlocks = std::llround(edges * (w / 8) * (h / 8));
      for (size_t l = 0; l < 3; ++l) {
        // the reach: as wide as three blocks a marked block where edges are sparse, all of the
        // level where they crowd
        const double levelPixels = static_cast<double>(c.levels[l].width) * c.levels[l].height;
        const double blockPixels = 64.0 / static_cast<double>(1 << (2 * l));
        n.reach[l] = std::llround(std::min(levelPixels, 3.0 * (1 + static_cast<double>(l)) * blockPixels *
                                                            static_cast<double>(n.edgeBlocks)));
        n.shaded[l] = std::llround(std::min(fill[l] * static_cast<double>(n.reach[l]),
                                            band[l] * blockPixels * static_cast<double>(n.edgeBlocks)));
      }
      frames.push_back({Effect::Ssao, c, n, 1.0});
    }
  // both sides of min's corner are in the frames, at every level
  for (size_t l = 0; l < 3; ++l) {
    int bandBinds = 0, fillBinds = 0;
    for (const CalibrationFrame& f : frames)
      (band[l] * 64.0 / (1 << (2 * l)) * static_cast<double>(f.counts.edgeBlocks) <
               fill[l] * static_cast<double>(f.counts.reach[l])
           ? bandBinds
           : fillBinds)++;
    ASSERT_GT(bandBinds, 2) << "level " << l;
    ASSERT_GT(fillBinds, 2) << "level " << l;
  }
  CostModel m;
  fitStencilFill(m, frames);
  for (size_t l = 0; l < 3; ++l) {
    EXPECT_NEAR(m.stencilFill[l], fill[l], 0.01) << "level " << l;
    EXPECT_NEAR(m.edgeBandFill[l] / band[l], 1.0, 0.02) << "level " << l;
  }
  // No frame reaches level 2: it keeps the model's figures.
  for (CalibrationFrame& f : frames) f.counts.reach[2] = f.counts.shaded[2] = 0;
  CostModel kept;
  kept.stencilFill[2] = 0.3;
  kept.edgeBandFill[2] = 5.0;
  fitStencilFill(kept, frames);
  EXPECT_EQ(kept.stencilFill[2], 0.3);
  EXPECT_EQ(kept.edgeBandFill[2], 5.0);
  EXPECT_NEAR(kept.stencilFill[0], fill[0], 0.01);
}

TEST(NeverSlower, TheSparsePremiumFallsToNothingAsTheStencilFillsTheLevel) {
  const Constants c = makeConstants(ssaoSettings(64, 32, 16), 1.0f);
  CostModel m;
  m.effect[static_cast<size_t>(Effect::Ssao)] = {10.0, 1.0, 0.0, 0.0, 0.0, 1.8};  // a, b, d, c, e, s
  FrameCounts n;
  n.hitPixels = n.searchedPixels = 1000;
  auto levelZeroMs = [&](int64_t shaded) {
    FrameCounts k = n;
    k.shaded = k.shadedHit = k.shadedSearched = {shaded, 0, 0, 0};
    return predictMrrMs(m, c, k);
  };
  EXPECT_NEAR(levelZeroMs(1000), predictFullMs(m, c, n), 1e-12) << "all of level 0: the dense frame";
  EXPECT_NEAR(levelZeroMs(1) - levelZeroMs(0), 26.0 * (1.0 + 0.8 * 0.999) * 1e-6, 1e-12) << "the first pixel: about s";
  for (double s : {1.0, 1.5, 2.0}) {
    m.effect[static_cast<size_t>(Effect::Ssao)].sparseFactor = s;
    for (int64_t shaded = 0; shaded < 1000; shaded += 50) EXPECT_LT(levelZeroMs(shaded), levelZeroMs(shaded + 50)) << s;
  }
}

// The rule sweep's frames (ruleSweepConfig): a path's frames are a function of the path alone.
// The port's continue the oracle's cycle, as when one run swept both (the committed port sweeps:
// its first frame, the arcade's catalogue camera, is 640×360 SSM-49, the cycle's fifth as 88 is 4
// past a multiple of its 12), and each path's frames reach every size, effect and sample count.
TEST(NeverSlower, ARuleSweepPathSweepsTheSameFramesWhateverElseTheRunSweeps) {
  const size_t perPath = 88;
  const SweepConfig port = ruleSweepConfig("gpu", 0, perPath), oracle = ruleSweepConfig("cpu", 0, perPath);
  EXPECT_EQ(std::make_tuple(port.effect, port.samples, port.width, port.height), std::make_tuple(Effect::Ssm, 49, 640, 360));
  EXPECT_EQ(std::make_tuple(oracle.effect, oracle.samples, oracle.width, oracle.height),
            std::make_tuple(Effect::Ssao, 16, 320, 180));
  for (const char* path : {"cpu", "gpu"}) {
    std::set<std::tuple<Effect, int, int, int>> seen;
    for (size_t i = 0; i < perPath; ++i) {
      const SweepConfig c = ruleSweepConfig(path, i, perPath);
      seen.insert({c.effect, c.samples, c.width, c.height});
    }
    EXPECT_EQ(seen.size(), 12u) << path << ": every size, effect and sample count";
  }
}

// The calibration's s and k (fitSparseFactorAndFixedCost): frames priced by a known model, at
// three sizes and several stencil coverages, are fitted back to it; a premium outside [1, 2] is
// held at the bound and k refitted alone, so the fitted rests are right on average.
TEST(NeverSlower, TheCalibrationFitsTheSparseFactorAndTheFixedCostBack) {
  auto framesPricedBy = [](const CostModel& truth) {
    std::vector<CalibrationFrame> frames;
    for (const auto& [w, h] : {std::pair{64, 32}, std::pair{128, 64}, std::pair{256, 144}})
      for (double fill : {0.05, 0.3, 0.8}) {
        const Constants c = makeConstants(ssaoSettings(w, h, 16), 1.0f);
        FrameCounts n;
        n.hitPixels = n.searchedPixels = static_cast<int64_t>(w) * h / 2;
        for (const LevelConstants& lc : c.levels) {
          const auto l = static_cast<size_t>(lc.index);
          const double levelPixels = static_cast<double>(lc.width) * lc.height;
          n.shaded[l] = std::llround(lc.index == c.coarsestEnabled ? levelPixels : fill * levelPixels);
          n.shadedHit[l] = n.shadedSearched[l] = std::llround(0.5 * static_cast<double>(n.shaded[l]));
        }
        frames.push_back({Effect::Ssao, c, n, predictMrrMs(truth, c, n)});
      }
    return frames;
  };
  auto fitted = [&](double s, double k) {
    CostModel truth;
    truth.nsPerBlendPixel = 2.0;
    truth.effect[static_cast<size_t>(Effect::Ssao)] = {10.0, 1.0, 0.0, 0.5, 0.0, s, k};  // a, b, d, c, e, s, k
    CostModel m = truth;
    m.effect[static_cast<size_t>(Effect::Ssao)].sparseFactor = 1.0;
    m.effect[static_cast<size_t>(Effect::Ssao)].fixedMs = 0.0;
    const std::vector<CalibrationFrame> frames = framesPricedBy(truth);
    fitSparseFactorAndFixedCost(m, Effect::Ssao, frames);
    double error = 0.0;
    for (const CalibrationFrame& f : frames) error += predictMrrMs(m, f.constants, f.counts) - f.restMs;
    return std::pair{m.effect[static_cast<size_t>(Effect::Ssao)], error};
  };
  const auto [inside, insideError] = fitted(1.4, 0.3);
  EXPECT_NEAR(inside.sparseFactor, 1.4, 1e-9);
  EXPECT_NEAR(inside.fixedMs, 0.3, 1e-9);
  EXPECT_NEAR(insideError, 0.0, 1e-9);
  for (const auto& [s, bound] : {std::pair{2.6, 2.0}, std::pair{0.7, 1.0}}) {
    const auto [held, error] = fitted(s, 0.3);
    EXPECT_EQ(held.sparseFactor, bound) << s;
    EXPECT_NEAR(error, 0.0, 1e-9) << s << ": k refitted to the mean residual";
    if (s > bound) EXPECT_GT(held.fixedMs, 0.3) << "k takes the premium the bound leaves out";
  }
  // No frame of the effect: s 1, k 0.
  CostModel none;
  none.effect[static_cast<size_t>(Effect::Ssgi)].sparseFactor = 1.7;
  none.effect[static_cast<size_t>(Effect::Ssgi)].fixedMs = 0.5;
  fitSparseFactorAndFixedCost(none, Effect::Ssgi, framesPricedBy(none));
  EXPECT_EQ(none.effect[static_cast<size_t>(Effect::Ssgi)].sparseFactor, 1.0);
  EXPECT_EQ(none.effect[static_cast<size_t>(Effect::Ssgi)].fixedMs, 0.0);
}

// The hand-made prices the formula tests read (SSAO's a, b, d, c, e, s; coarse G-buffer, blend,
// edges and masks per pixel), in ns.
CostModel handMadeModel() {
  CostModel m;
  m.effect[static_cast<size_t>(Effect::Ssao)] = {10.0, 1.0, 2.0, 0.5, 0.0, 1.5};  // a, b, d, c, e, s
  m.nsPerCoarseGbufferPixel = 3.0;
  m.nsPerBlendPixel = 5.0;
  m.nsPerEdgePixel = 7.0;
  m.nsPerMaskPixel = 11.0;
  return m;
}

// SPEC §11's formulas on hand-made counts (level sizes of a 64×32 frame: 2048, 512, 128, 32).
TEST(NeverSlower, PredictionCountsGeometryBackgroundCoarseGbuffersAndBlend) {
  CostModel m = handMadeModel();
  const Constants c = makeConstants(ssaoSettings(64, 32, 16), 1.0f);
  FrameCounts n;
  n.hitPixels = n.searchedPixels = 1024;  // half the frame on geometry, all of it paying the effect
  // full: 1024 × (10 + 16) on geometry + 1024 × 0.5 off it + 2048 × ½ × 2 (d on geometry)
  EXPECT_NEAR(predictFullMs(m, c, n), (1024.0 * 26 + 1024.0 * 0.5 + 2048.0 * 0.5 * 2) * 1e-6, 1e-12);
  n.shaded = {100, 50, 20, 32};
  n.shadedHit = n.shadedSearched = {60, 25, 10, 16};
  // s_ℓ = 1 + (s − 1)(1 − q_ℓ), q_ℓ the share of the level's H_a / s_ℓ² paying pixels shaded: 1.5
  // for a stencil of none, 1 for one of all (level 3: 16 of 1024 / 64).
  auto sl = [](double paying, double scale) { return 1.0 + 0.5 * (1.0 - paying * scale * scale / 1024.0); };
  EXPECT_EQ(sl(16, 8), 1.0);
  // on geometry × 26 × s_ℓ + off × 0.5 + level pixels × 2 + coarse pixels × 3 (a copy of level
  // 0's, on geometry or not) + blend 2048 × 5
  const double levelPixels = 2048.0 + 512 + 128 + 32, coarse = 512.0 + 128 + 32;
  const double stencilled = 60.0 * sl(60, 1) + 25.0 * sl(25, 2) + 10.0 * sl(10, 4) + 16.0 * sl(16, 8);
  const double expected = stencilled * 26 + 91.0 * 0.5 + levelPixels * 0.5 * 2 + coarse * 3 + 2048.0 * 5;
  EXPECT_NEAR(predictMrrMs(m, c, n), expected * 1e-6, 1e-12);
  // The floor: edges and masks over P_0, the coarse G-buffers and blend, d over every shaded
  // level, and level 3 shaded whole (half its pixels on geometry, on average: all 16 of its
  // paying pixels, s_3 = 1).
  const double floorNs = 2048.0 * (7 + 11) + coarse * 3 + 2048.0 * 5 +
                         levelPixels * 0.5 * 2 + 32.0 * (0.5 * 26 * 1.0 + 0.5 * 0.5);
  EXPECT_NEAR(predictMrrFloorMs(m, c, n), floorNs * 1e-6, 1e-12);
  // Silhouettes are shaded at every level (B_ℓ): at level 0 each is on geometry (26 at s_0), at
  // levels 1 and 2 they pay what an average pixel does (half of them paying); level 3 is counted
  // whole already.
  n.silhouette = {40, 20, 8, 2};
  EXPECT_NEAR(predictMrrFloorMs(m, c, n),
              (floorNs + 40.0 * 26 * sl(40, 1) + 20.0 * (0.5 * 26 * sl(10, 2) + 0.5 * 0.5) +
               8.0 * (0.5 * 26 * sl(4, 4) + 0.5 * 0.5)) *
                  1e-6,
              1e-12);
  // The floor never exceeds what the method pays from the edges on: ε + μ, then the late prediction.
  EXPECT_LE(predictMrrFloorMs(m, c, n), predictMrrMs(m, c, n) + 2048.0 * (7 + 11) * 1e-6);
  // k, the method's per-frame set-up, adds to its prediction and its floor, never to full's.
  const double fullBefore = predictFullMs(m, c, n), mrrBefore = predictMrrMs(m, c, n);
  const double floorBefore = predictMrrFloorMs(m, c, n);
  m.effect[static_cast<size_t>(Effect::Ssao)].fixedMs = 3.25;
  EXPECT_EQ(predictFullMs(m, c, n), fullBefore);
  EXPECT_NEAR(predictMrrMs(m, c, n), mrrBefore + 3.25, 1e-12);
  EXPECT_NEAR(predictMrrFloorMs(m, c, n), floorBefore + 3.25, 1e-12);
  // κ, the edges' and masks' per-frame set-up, adds to the floor alone (the late decision comes
  // after the edges and masks are paid).
  m.edgesMasksFixedMs = 0.75;
  EXPECT_NEAR(predictMrrFloorMs(m, c, n), floorBefore + 3.25 + 0.75, 1e-12);
  EXPECT_NEAR(predictMrrMs(m, c, n), mrrBefore + 3.25, 1e-12);
  EXPECT_EQ(predictFullMs(m, c, n), fullBefore);
  m.edgesMasksFixedMs = 0.0;
  // k₀, a full frame's own set-up, adds to full's alone.
  m.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs = 1.5;
  EXPECT_NEAR(predictFullMs(m, c, n), fullBefore + 1.5, 1e-12);
  EXPECT_NEAR(predictMrrMs(m, c, n), mrrBefore + 3.25, 1e-12);
  m.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs = 0.0;
  // H_p: SSM's pixels paying PCF cost e per sample more, at the sparse factor in the method.
  CostModel ssm = m;
  ssm.effect[static_cast<size_t>(Effect::Ssm)] = {10.0, 0.0, 0.0, 0.5, 3.0, 1.5, 0.0, 0.0};
  Settings ssmSettings = defaultSettings(Effect::Ssm);
  ssmSettings.width = 64;
  ssmSettings.height = 32;
  ssmSettings.ssm.samples = 16;
  const Constants cs = makeConstants(ssmSettings, 1.0f);
  const double ssmFull = predictFullMs(ssm, cs, n), ssmMrr = predictMrrMs(ssm, cs, n);
  n.pcfPixels = 400;
  n.shadedPcf = {30, 10, 0, 4};
  EXPECT_NEAR(predictFullMs(ssm, cs, n) - ssmFull, 400.0 * 3 * 16 * 1e-6, 1e-12);
  EXPECT_NEAR(predictMrrMs(ssm, cs, n) - ssmMrr, (30.0 * sl(60, 1) + 10.0 * sl(25, 2) + 4.0 * sl(16, 8)) * 3 * 16 * 1e-6,
              1e-12);
  // H_a: SSM's pixels facing away from the light pay c, as background does, not a; and q_ℓ is a
  // share of the pixels that pay.
  auto ssmShadingNs = [&](double searched) {
    double ns = 0.0;
    for (size_t l = 0; l < kLevelCount; ++l) {
      const double scale = static_cast<double>(1 << l), paying = static_cast<double>(n.shadedSearched[l]);
      const double factor = 1.0 + 0.5 * (1.0 - std::min(1.0, paying * scale * scale / searched));
      ns += (paying * 10 + static_cast<double>(n.shadedPcf[l]) * 3 * 16) * factor +
            (static_cast<double>(n.shaded[l]) - paying) * 0.5;
    }
    return ns;
  };
  const double withAll = predictFullMs(ssm, cs, n), mrrWithAll = predictMrrMs(ssm, cs, n);
  const double shadingWithAll = ssmShadingNs(1024.0);
  n.searchedPixels = 1024 - 200;
  n.shadedSearched = {50, 25, 10, 16};
  EXPECT_NEAR(withAll - predictFullMs(ssm, cs, n), 200.0 * (10 - 0.5) * 1e-6, 1e-12);
  EXPECT_NEAR(mrrWithAll - predictMrrMs(ssm, cs, n), (shadingWithAll - ssmShadingNs(824.0)) * 1e-6, 1e-12);
  // ν: SSM's searching pixels pay ν f_ℓ more, f_0 = f̄ = F / (4 H_a) texels, f_ℓ = min(s_ℓ f̄, 15.75),
  // at the sparse factor in the method; nothing without a footprint.
  {
    CostModel memory = ssm;
    memory.effect[static_cast<size_t>(Effect::Ssm)].nsPerFootprintTexel = 2.0;
    EXPECT_EQ(predictFullMs(memory, cs, n), predictFullMs(ssm, cs, n));
    EXPECT_EQ(predictMrrMs(memory, cs, n), predictMrrMs(ssm, cs, n));
    FrameCounts wide = n;
    wide.searchedFootprint = 3 * 4 * wide.searchedPixels;  // f̄ = 3 texels
    EXPECT_NEAR(footprintTexels(cs.levels[2], wide), 12.0, 1e-12);
    EXPECT_NEAR(footprintTexels(cs.levels[3], wide), 15.75, 1e-12) << "at most a line's 16 texels, less a step";
    EXPECT_NEAR(predictFullMs(memory, cs, wide) - predictFullMs(ssm, cs, wide), 824.0 * 2 * 3 * 1e-6, 1e-12);
    auto slSearched = [&](double paying, double scale) {
      return 1.0 + 0.5 * (1.0 - std::min(1.0, paying * scale * scale / 824.0));  // level 3: all 16 of 824 / 64, 1
    };
    const double levels = 50.0 * 3 * slSearched(50, 1) + 25.0 * 6 * slSearched(25, 2) + 10.0 * 12 * slSearched(10, 4) +
                          16.0 * 15.75 * slSearched(16, 8);
    EXPECT_NEAR(predictMrrMs(memory, cs, wide) - predictMrrMs(ssm, cs, wide), levels * 2 * 1e-6, 1e-12);
    EXPECT_GT(predictMrrFloorMs(memory, cs, wide), predictMrrFloorMs(ssm, cs, wide)) << "the floor's searches pay it too";
  }
  // β_f: the blend's finer levels, per full-res pixel where they can show: under S_2, the
  // coarsest level below the coarsest (3), which the closure makes hold every finer level's
  // blocks; in the prediction over |S_2| and in the floor over the silhouettes B_2.
  {
    CostModel fine = m;
    fine.nsPerFineBlendPixel = 0.25;
    EXPECT_NEAR(predictMrrMs(fine, c, n) - predictMrrMs(m, c, n), 20.0 * 16 * 0.25 * 1e-6, 1e-12);
    EXPECT_NEAR(predictMrrFloorMs(fine, c, n) - predictMrrFloorMs(m, c, n), 8.0 * 16 * 0.25 * 1e-6, 1e-12);
    EXPECT_EQ(predictFullMs(fine, c, n), predictFullMs(m, c, n));
  }
  // ρ, the rule's own counts per full-res pixel, is the method's alone, early and late.
  {
    CostModel rule = m;
    rule.effect[static_cast<size_t>(Effect::Ssao)].nsPerRulePixel = 2.0;
    EXPECT_NEAR(predictMrrMs(rule, c, n) - predictMrrMs(m, c, n), 2048.0 * 2 * 1e-6, 1e-12);
    EXPECT_NEAR(predictMrrFloorMs(rule, c, n) - predictMrrFloorMs(m, c, n), 2048.0 * 2 * 1e-6, 1e-12);
    EXPECT_EQ(predictFullMs(rule, c, n), predictFullMs(m, c, n));
  }
  // β₀, full's own blend (a copy of level 0), is paid by both modes alike.
  {
    CostModel copy = m;
    copy.nsPerFullBlendPixel = 0.5;
    EXPECT_NEAR(predictFullMs(copy, c, n) - predictFullMs(m, c, n), 2048.0 * 0.5 * 1e-6, 1e-12);
    EXPECT_NEAR(predictMrrMs(copy, c, n) - predictMrrMs(m, c, n), 2048.0 * 0.5 * 1e-6, 1e-12);
    EXPECT_NEAR(predictMrrFloorMs(copy, c, n) - predictMrrFloorMs(m, c, n), 2048.0 * 0.5 * 1e-6, 1e-12);
  }
  // A frame all background: full costs c per pixel, nothing on geometry.
  n.hitPixels = n.searchedPixels = 0;
  n.pcfPixels = 0;
  EXPECT_NEAR(predictFullMs(m, c, n), 2048.0 * 0.5 * 1e-6, 1e-12) << "and d only on geometry: none";
}

// countHits against the definitions, pixel by pixel, on random hit images (clumps and speckle,
// a padded image wider and taller than the frame) with a PCF sample of all three kinds: H, H_a,
// H_p, B_ℓ at every level and the silhouette blocks, at 1 and 2 threads.
TEST(NeverSlower, CountHitsIsItsDefinitionOnRandomImages) {
  std::mt19937 rng(18);
  for (const auto [w, h, hw, hh] : {std::array{61, 35, 64, 40}, std::array{64, 32, 64, 32}, std::array{1, 9, 1, 9},
                                    std::array{97, 3, 104, 8}}) {
    const Constants c = makeConstants(ssaoSettings(w, h, 16), 1.0f);
    ImageU8 hit(hw, hh, 1, 0);
    const int density = static_cast<int>(rng() % 100);
    for (uint8_t& v : hit.data) v = static_cast<uint8_t>(static_cast<int>(rng() % 100) < density);
    ImageU8 pcf((hw + 7) / 8, (hh + 7) / 8, 1, 0);
    for (uint8_t& v : pcf.data)  // none, search, PCF, with a footprint of 0 to 63 steps above
      v = static_cast<uint8_t>(rng() % 3 | (rng() % 64) << kPcfSampleClassBits);
    int64_t hits = 0, searched = 0, paysPcf = 0, footprint = 0;
    std::array<std::set<std::pair<int, int>>, kLevelCount> blocks;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!hit.at(x, y)) continue;
        ++hits;
        const uint8_t pays = pcfSampleValue(pcf, x, y);
        searched += pcfSampleClass(pays) != kPcfSampleNone;
        paysPcf += pcfSampleClass(pays) == kPcfSamplePcf;
        footprint += pcfSampleClass(pays) != kPcfSampleNone ? pcfSampleFootprintSteps(pays) : 0;
        bool silhouette = false;
        for (const auto [dx, dy] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}})
          silhouette |= hit.contains(x + dx, y + dy) && !hit.at(x + dx, y + dy);
        if (silhouette)
          for (int l = 0; l < kLevelCount; ++l) blocks[static_cast<size_t>(l)].insert({x >> l, y >> l});
      }
    for (const int threads : {1, 2}) {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
      FrameCounts n;
      ImageU8 silhouetteBlocks;
      countHits(n, hit, pcf, c, &silhouetteBlocks);
      const std::string what = std::to_string(w) + "x" + std::to_string(h) + ", " + std::to_string(threads) + " threads";
      EXPECT_EQ(n.hitPixels, hits) << what;
      EXPECT_EQ(n.searchedPixels, searched) << what;
      EXPECT_EQ(n.pcfPixels, paysPcf) << what;
      EXPECT_EQ(n.searchedFootprint, footprint) << what;
      for (int l = 0; l < kLevelCount; ++l)
        EXPECT_EQ(n.silhouette[static_cast<size_t>(l)], static_cast<int64_t>(blocks[static_cast<size_t>(l)].size()))
            << what << ", level " << l;
      for (int by = 0; by < silhouetteBlocks.height; ++by)
        for (int bx = 0; bx < silhouetteBlocks.width; ++bx)
          EXPECT_EQ(silhouetteBlocks.at(bx, by) != 0, blocks[3].count({bx, by}) == 1) << what << ", block " << bx << "," << by;
      FrameCounts unsampled;
      countHits(unsampled, hit, ImageU8(), c);
      EXPECT_EQ(unsampled.searchedPixels, hits) << what << ": without a sample every pixel on geometry searches";
      EXPECT_EQ(unsampled.pcfPixels, 0) << what;
      EXPECT_EQ(unsampled.searchedFootprint, 0) << what << ": nor a footprint";
    }
  }
}

// The counts the rule reads: H over W×H and a level pixel on geometry where its full-res
// pixel (x·s + s/2, y·s + s/2) is.
TEST(NeverSlower, CountsShadedPixelsOnGeometryPerLevel) {
  const Constants c = makeConstants(ssaoSettings(64, 32, 16), 1.0f);
  ImageU8 hit(64, 32, 1, 0);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 20; ++x) hit.at(x, y) = 1;  // the left 20 columns
  Masks masks;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    masks[static_cast<size_t>(l)].stencil = ImageU8(lc.width, lc.height, 1, 1);  // every pixel
  }
  FrameCounts n;
  countHits(n, hit, ImageU8(), c);
  countForRule(n, masks, c, hit, ImageU8());
  EXPECT_EQ(n.pcfPixels, 0) << "no PCF sample: no pixels paying PCF";
  EXPECT_EQ(n.hitPixels, 20 * 32);
  EXPECT_EQ(n.shaded[0], 64 * 32);
  EXPECT_EQ(n.shadedHit[0], 20 * 32);
  // Level 1: columns x with 2x + 1 < 20, x ≤ 9: 10 of 32 per row, 16 rows.
  EXPECT_EQ(n.shadedHit[1], 10 * 16);
  // Level 3: 8x + 4 < 20, x ≤ 1: 2 of 8 per row, 4 rows.
  EXPECT_EQ(n.shadedHit[3], 2 * 4);
  EXPECT_EQ(n.searchedPixels, 20 * 32) << "no sample: every pixel on geometry pays the effect";
  EXPECT_EQ(n.shadedSearched, n.shadedHit);
  // Silhouettes: column 19 (its right neighbour is off geometry; column 0's left one is outside
  // the image, which is no edge), and its blocks at every level.
  EXPECT_EQ(n.silhouette, (std::array<int64_t, kLevelCount>{32, 16, 8, 4}));
  // SSM's PCF sample, one pixel in 8×8 (an 8×4 image): its top two rows pay PCF, so the top 16
  // full-res rows do; its bottom row faces away from the light, so rows 24–31 pay nothing.
  // H_a and H_p count only pixels on geometry.
  ImageU8 pcf(8, 4, 1, kPcfSampleSearch);
  for (int x = 0; x < 8; ++x) {
    pcf.at(x, 0) = pcf.at(x, 1) = kPcfSamplePcf;
    pcf.at(x, 3) = kPcfSampleNone;
  }
  countHits(n, hit, pcf, c);
  countForRule(n, masks, c, hit, pcf);
  EXPECT_EQ(n.pcfPixels, 20 * 16);
  EXPECT_EQ(n.searchedPixels, 20 * 24);
  EXPECT_EQ(n.shadedPcf[0], 20 * 16);
  EXPECT_EQ(n.shadedPcf[1], 10 * 8);  // rows 2y + 1 < 16
  EXPECT_EQ(n.shadedPcf[3], 2 * 2);   // rows 8y + 4 < 16
  EXPECT_EQ(n.shadedSearched[0], 20 * 24);
  EXPECT_EQ(n.shadedSearched[1], 10 * 12);  // rows 2y + 1 < 24
  EXPECT_EQ(n.shadedSearched[3], 2 * 3);    // rows 8y + 4 < 24
  EXPECT_EQ(n.shadedHit[1], 10 * 16) << "unchanged";
}

// SPEC §11's edge sample, counted and priced on a hand-made sample: a 64×32 frame (an 8×4 block
// grid), its left 20 columns on geometry (a silhouette down column 19, in block column 2), one
// sampled edge block at (5, 1).
TEST(NeverSlower, TheEdgeSampleEstimatesTheStencilsBeforeTheEdges) {
  const Constants c = makeConstants(ssaoSettings(64, 32, 16), 1.0f);
  ImageU8 hit(64, 32, 1, 0);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 20; ++x) hit.at(x, y) = 1;
  ImageU8 sample(8, 4, 1, 0);
  sample.at(5, 1) = 1;
  FrameCounts n;
  ImageU8 silhouetteBlocks;
  countHits(n, hit, ImageU8(), c, &silhouetteBlocks);
  ASSERT_EQ(silhouetteBlocks.width, 8);
  ASSERT_EQ(silhouetteBlocks.height, 4);
  for (int by = 0; by < 4; ++by)
    for (int bx = 0; bx < 8; ++bx) EXPECT_EQ(silhouetteBlocks.at(bx, by), bx == 2) << bx << "," << by;
  countEdgeSample(n, sample, silhouetteBlocks, hit, c);
  EXPECT_EQ(n.edgeBlocks, 1 + 4) << "the sampled block and the silhouette's column of blocks";
  // R_ℓ: the blocks within ceil(r_ℓ / b_ℓ) blocks (b_ℓ = 8 / s_ℓ level pixels a block) of one of
  // those, and every finer level's: as wide as the widest reach so far
  int reachBlocks = 0;
  for (int l = 0; l < 3; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const int b = 8 >> l;
    reachBlocks = std::max(reachBlocks, (lc.blurRadius + b - 1) / b);
    int64_t blocks = 0, hits = 0;
    for (int by = 0; by < 4; ++by)
      for (int bx = 0; bx < 8; ++bx) {
        const bool nearSample = std::abs(bx - 5) <= reachBlocks && std::abs(by - 1) <= reachBlocks;
        const bool nearSilhouette = std::abs(bx - 2) <= reachBlocks;
        if (!nearSample && !nearSilhouette) continue;
        ++blocks;
        hits += 8 * std::clamp(20 - 8 * bx, 0, 8);  // block columns 0 and 1 whole, 2 half
      }
    EXPECT_EQ(n.reach[static_cast<size_t>(l)], blocks * b * b) << "level " << l;
    EXPECT_EQ(n.reachHits[static_cast<size_t>(l)], hits) << "level " << l;
  }
  EXPECT_EQ(n.reach[3], 0);
  // The estimate: |S_ℓ| = max(B_ℓ, min(φ_ℓ |R_ℓ|, η_ℓ |Ê| (8/s_ℓ)²)) on geometry in R_ℓ's share,
  // the coarsest level whole. Level 0 takes the band (η 0.5: half a block per marked block), levels
  // 1 and 2 the fill.
  CostModel m;
  m.effect[static_cast<size_t>(Effect::Ssao)] = {10.0, 1.0, 0.0, 0.5, 0.0, 1.5};  // a, b, d, c, e, s
  m.stencilFill = {0.5, 0.25, 1.0};
  m.edgeBandFill = {0.5, 100.0, 100.0};
  const FrameCounts est = estimateStencils(m, c, n);
  ASSERT_LT(0.5 * static_cast<double>(n.edgeBlocks) * 64.0, 0.5 * static_cast<double>(n.reach[0]))
      << "the frame's level 0 must be one where the band binds";
  for (int l = 0; l < 3; ++l) {
    const auto i = static_cast<size_t>(l);
    const double band = m.edgeBandFill[i] * static_cast<double>(n.edgeBlocks) * 64.0 / static_cast<double>(1 << (2 * l));
    const double shaded = std::max(static_cast<double>(n.silhouette[i]),
                                   std::min(m.stencilFill[i] * static_cast<double>(n.reach[i]), band));
    EXPECT_EQ(est.shaded[i], std::llround(shaded)) << "level " << l;
    const double share = static_cast<double>(n.reachHits[i]) / static_cast<double>(n.reach[i] << (2 * l));
    EXPECT_EQ(est.shadedHit[i], std::llround(shaded * share)) << "level " << l;
    EXPECT_EQ(est.shadedSearched[i], est.shadedHit[i]) << "no PCF sample: every pixel on geometry searches";
  }
  EXPECT_EQ(est.shaded[3], 32);
  EXPECT_EQ(est.shadedHit[3], std::llround(32.0 * 640 / 2048));
  // Priced: the edges and masks (P_0 (ε + μ) + H ε_h + A μ_A + κ) and the rest on those counts.
  m.nsPerEdgePixel = 7.0;
  m.nsPerEdgeHitPixel = 2.0;
  m.nsPerMaskPixel = 11.0;
  m.nsPerMaskReachPixel = 3.0;
  m.edgesMasksFixedMs = 0.5;
  const double reach = static_cast<double>(n.reach[0] + n.reach[1] + n.reach[2]);
  EXPECT_NEAR(predictMrrEstimateMs(m, c, n),
              (2048.0 * 18 + 640.0 * 2 + reach * 3) * 1e-6 + 0.5 + predictMrrMs(m, c, est), 1e-12);
  // The early decision takes the larger of the floor and what going on costs: the edges and
  // masks, then the cheaper of R and F. With no spread (w = 0) a full frame priced between the
  // floor and the estimate falls back early, where the floor alone would have kept the method.
  const double floorMs = predictMrrFloorMs(m, c, n), estimateMs = predictMrrEstimateMs(m, c, n);
  const double edgesMasksMs = predictEdgesMasksMs(m, c, n), restMs = estimateMs - edgesMasksMs;
  EXPECT_NEAR(edgesMasksMs, (2048.0 * 18 + 640.0 * 2 + reach * 3) * 1e-6 + 0.5, 1e-12);
  ASSERT_LT(floorMs, estimateMs);
  m.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs = 0.5 * (floorMs + estimateMs) - predictFullMs(m, c, n);
  const double fullMs = predictFullMs(m, c, n);
  const FallbackDecision early = decideEarly(m, c, n);
  EXPECT_TRUE(early.fellBack);
  EXPECT_NEAR(early.predictedMrrMs, edgesMasksMs + std::min(restMs, fullMs), 1e-12);
  // With a spread, R may be cheaper than R̂, and then the stencils would keep the method: going on
  // is worth E[min(R, F)] over R uniform on R̂ (1 ± w). With free edges and masks and F 2% under
  // R̂, no spread falls back early; a spread goes on to decide on the stencils; dear edges and
  // masks (half of R̂) fall back whatever the spread.
  CostModel free = m;
  free.nsPerEdgePixel = free.nsPerMaskPixel = free.nsPerEdgeHitPixel = free.nsPerMaskReachPixel = 0.0;
  free.edgesMasksFixedMs = 0.0;
  free.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs = 0.0;
  const double freeFull = predictFullMs(free, c, n);
  free.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs = 0.98 * restMs - freeFull;
  const double f98 = predictFullMs(free, c, n);
  ASSERT_NEAR(f98, 0.98 * restMs, 1e-12);
  ASSERT_LT(predictMrrFloorMs(free, c, n), f98) << "the floor keeps the method";
  EXPECT_TRUE(decideEarly(free, c, n).fellBack) << "no spread: R̂ is R";
  free.estimateSpread = 0.5;
  const double lo = 0.5 * restMs, hi = 1.5 * restMs;
  const double expectedMin = (0.5 * (f98 * f98 - lo * lo) + f98 * (hi - f98)) / (hi - lo);
  EXPECT_NEAR(predictContinuingMs(free, c, n, f98), expectedMin, 1e-12);
  EXPECT_LT(expectedMin, f98);
  EXPECT_FALSE(decideEarly(free, c, n).fellBack) << "a spread: R may be under F, and deciding later costs nothing";
  CostModel dear = free;
  dear.edgesMasksFixedMs = 0.5 * restMs;
  EXPECT_NEAR(predictContinuingMs(dear, c, n, f98), 0.5 * restMs + expectedMin, 1e-12);
  EXPECT_TRUE(decideEarly(dear, c, n).fellBack) << "deciding later costs half of R̂";
  // The floor first: where it is no less than full's rest, decideEarly is decideOnFloor's
  // decision, whatever the edge sample found (none, or edges everywhere); under it, the floor
  // alone keeps the method and decideEarly looks further.
  {
    CostModel floorModel = m;
    floorModel.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs = 0.0;
    floorModel.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs =
        0.9 * predictMrrFloorMs(floorModel, c, n) - predictFullMs(floorModel, c, n);
    FrameCounts unsampled = n;
    unsampled.edgeBlocks = 0;
    unsampled.reach = unsampled.reachHits = {};
    for (const FrameCounts* counts : {static_cast<const FrameCounts*>(&n), static_cast<const FrameCounts*>(&unsampled)}) {
      const FallbackDecision onFloor = decideOnFloor(floorModel, c, *counts);
      const FallbackDecision early = decideEarly(floorModel, c, *counts);
      EXPECT_TRUE(onFloor.fellBack && onFloor.onFloor && onFloor.early);
      EXPECT_TRUE(early.fellBack && early.onFloor);
      EXPECT_EQ(early.predictedMrrMs, predictMrrFloorMs(floorModel, c, n));
      EXPECT_NEAR(early.predictedMrrMs, early.predictedFullMs / 0.9, 1e-9);
    }
    const FallbackDecision underFloor = decideOnFloor(m, c, n);
    EXPECT_FALSE(underFloor.fellBack || underFloor.onFloor);
    EXPECT_EQ(underFloor.predictedMrrMs, predictMrrFloorMs(m, c, n));
    EXPECT_FALSE(decideEarly(m, c, n).onFloor);
  }
  // With nothing to start from (no sampled edge, no silhouette) there is no reach: the estimate
  // is the coarsest level's alone, and it keeps the method.
  FrameCounts noEdges = n;
  countEdgeSample(noEdges, ImageU8(8, 4, 1, 0), ImageU8(8, 4, 1, 0), hit, c);
  EXPECT_EQ(noEdges.edgeBlocks, 0);
  EXPECT_EQ(noEdges.reach, (std::array<int64_t, kLevelCount>{}));
  EXPECT_FALSE(decideEarly(m, c, noEdges).fellBack);
}

// SPEC §11 prices mrr-effect: its masks' footprint and widening (μ_e, per padded
// pixel) before the stencils, so in the early decision and the floor but not in the rest; its
// a-posteriori term (μ_v, per pixel of each refined level) after them, in the rest and the floor.
// mrr's predictions do not move. On a 64×32 frame (levels 2048, 512, 128, 32 pixels).
TEST(NeverSlower, PricesMrrEffectsMasksAndItsAPosterioriPasses) {
  CostModel m = handMadeModel();
  const Constants mrr = makeConstants(ssaoSettings(64, 32, 16), 1.0f);
  Settings es = ssaoSettings(64, 32, 16, Mode::MrrEffect);
  es.effectMask.budget = 0.0f;  // a priori: no a-posteriori term (SPEC §12.4's budget refines)
  const Constants effect = makeConstants(es, 1.0f);
  es.effectMask.posterior = 0.3f;
  const Constants posterior = makeConstants(es, 1.0f);
  es.effectMask.posteriorFinest = 1;
  const Constants posteriorFrom1 = makeConstants(es, 1.0f);
  ASSERT_EQ(mrr.levels[0].width * mrr.levels[0].height, 2048);
  ASSERT_EQ(mrr.coarsestEnabled, 3);
  FrameCounts n;
  n.hitPixels = n.searchedPixels = 1024;
  n.silhouette = {40, 20, 8, 2};
  n.shaded = {100, 50, 20, 32};
  n.shadedHit = n.shadedSearched = {60, 25, 10, 16};
  struct Predictions {
    double edgesMasks, floor, rest;
  };
  auto predict = [&](const CostModel& model, const Constants& c) {
    return Predictions{predictEdgesMasksMs(model, c, n), predictMrrFloorMs(model, c, n), predictMrrMs(model, c, n)};
  };
  // Unpriced (μ_e = μ_v = 0), every mode predicts what mrr does.
  const Predictions base = predict(m, mrr);
  for (const Constants* c : {&effect, &posterior, &posteriorFrom1}) {
    const Predictions p = predict(m, *c);
    EXPECT_EQ(p.edgesMasks, base.edgesMasks);
    EXPECT_EQ(p.floor, base.floor);
    EXPECT_EQ(p.rest, base.rest);
  }
  CostModel priced = m;
  priced.nsPerEffectMaskPixel = 4.0;
  priced.nsPerRefinePixel = 2.0;
  // mrr: untouched.
  EXPECT_EQ(predict(priced, mrr).edgesMasks, base.edgesMasks);
  EXPECT_EQ(predict(priced, mrr).floor, base.floor);
  EXPECT_EQ(predict(priced, mrr).rest, base.rest);
  EXPECT_EQ(effectMaskNs(priced, mrr), 0.0);
  EXPECT_EQ(refineNs(priced, mrr), 0.0);
  // mrr-effect a priori: P_0 μ_e with the masks, nothing in the rest.
  const double masksNs = 2048.0 * 4;
  EXPECT_EQ(effectMaskNs(priced, effect), masksNs);
  EXPECT_EQ(refineNs(priced, effect), 0.0);
  EXPECT_NEAR(predict(priced, effect).edgesMasks - base.edgesMasks, masksNs * 1e-6, 1e-12);
  EXPECT_NEAR(predict(priced, effect).floor - base.floor, masksNs * 1e-6, 1e-12);
  EXPECT_EQ(predict(priced, effect).rest, base.rest);
  // The a-posteriori term: levels 0 to 2 refined (the coarsest is shaded first, never refined),
  // or 1 and 2 from +l1, at μ_v per level pixel, in the rest and the floor.
  const double refineAll = (2048.0 + 512 + 128) * 2, refineFrom1 = (512.0 + 128) * 2;
  EXPECT_EQ(refineNs(priced, posterior), refineAll);
  EXPECT_EQ(refineNs(priced, posteriorFrom1), refineFrom1);
  EXPECT_NEAR(predict(priced, posterior).rest - base.rest, refineAll * 1e-6, 1e-12);
  EXPECT_NEAR(predict(priced, posterior).floor - base.floor, (masksNs + refineAll) * 1e-6, 1e-12);
  EXPECT_NEAR(predict(priced, posteriorFrom1).rest - base.rest, refineFrom1 * 1e-6, 1e-12);
  // So a frame mrr shades multires (full 1 ms dearer than the most mrr's early decision
  // predicts) falls back for mrr-effect when its masks cost 2 ms more.
  CostModel decide = m;
  const double mrrEarly = std::max(predictMrrFloorMs(decide, mrr, n), predictMrrEstimateMs(decide, mrr, n));
  decide.effect[static_cast<size_t>(Effect::Ssao)].fullFixedMs = mrrEarly + 1.0 - predictFullMs(decide, mrr, n);
  decide.nsPerEffectMaskPixel = 2e6 / 2048.0;
  EXPECT_FALSE(decideEarly(decide, mrr, n).fellBack);
  CostModel unpriced = decide;
  unpriced.nsPerEffectMaskPixel = 0.0;
  EXPECT_FALSE(decideEarly(unpriced, effect, n).fellBack) << "unpriced, mrr-effect is taken for mrr";
  EXPECT_TRUE(decideEarly(decide, effect, n).fellBack) << "priced, its masks' 2 ms decide the frame";
}

TEST(NeverSlower, CostModelRoundTripsThroughJsonAndRejectsAMissingKey) {
  const CostModel m = CostModel::defaults("gpu");
  const CostModel back = CostModel::fromJson(m.toJson());
  EXPECT_EQ(back.toJson(), m.toJson());
  for (const char* key : {"ns_per_blend_pixel", "ns_per_fine_blend_pixel", "ns_per_full_blend_pixel", "ns_per_coarse_gbuffer_pixel",
                          "ns_per_edge_pixel", "ns_per_edge_hit_pixel", "ns_per_mask_reach_pixel", "stencil_fill",
                          "edge_band_fill", "estimate_spread",
                          "edges_masks_fixed_ms", "ns_per_effect_mask_pixel", "ns_per_refine_pixel"}) {
    nlohmann::json broken = m.toJson();
    broken.erase(key);
    EXPECT_THROW(CostModel::fromJson(broken), MrrError) << key;
  }
  nlohmann::json older = m.toJson();  // a file from before the background cost: none
  older["effects"]["ssao"].erase("ns_per_background_pixel");
  EXPECT_THROW(CostModel::fromJson(older), MrrError);
  nlohmann::json shortFill = m.toJson();  // φ for every level below the coarsest, no fewer
  shortFill["stencil_fill"] = {0.5, 0.5};
  EXPECT_THROW(CostModel::fromJson(shortFill), MrrError);
  // η for every level below the coarsest, each a positive number (a band of no pixels, or of
  // fewer than none, would estimate every stencil at its silhouettes alone)
  for (const nlohmann::json& band : {nlohmann::json{1.0, 2.0}, nlohmann::json{1.0, 0.0, 8.0}, nlohmann::json{1.0, -2.0, 8.0},
                                     nlohmann::json{1.0, "2", 8.0}}) {
    nlohmann::json broken = m.toJson();
    broken["edge_band_fill"] = band;
    EXPECT_THROW(CostModel::fromJson(broken), MrrError) << band.dump();
  }
  nlohmann::json noRule = m.toJson();  // a file from before the rule's cost was measured
  noRule["effects"]["ssm"].erase("ns_per_rule_pixel");
  EXPECT_THROW(CostModel::fromJson(noRule), MrrError);
  nlohmann::json noFootprint = m.toJson();  // a file from before the map footprint was priced
  noFootprint["effects"]["ssm"].erase("ns_per_footprint_texel");
  EXPECT_THROW(CostModel::fromJson(noFootprint), MrrError);
  for (const nlohmann::json& nu : {nlohmann::json(-1.0), nlohmann::json("3")}) {  // ν: a number, no cheaper for a wider footprint
    nlohmann::json broken = m.toJson();
    broken["effects"]["ssm"]["ns_per_footprint_texel"] = nu;
    EXPECT_THROW(CostModel::fromJson(broken), MrrError) << nu.dump();
  }
  // s outside [1, 2]: SPEC §11's per-level premium would price a level lower as its stencil grew.
  for (double s : {0.9, 2.5}) {
    nlohmann::json premium = m.toJson();
    premium["effects"]["ssgi"]["sparse_factor"] = s;
    EXPECT_THROW(CostModel::fromJson(premium), MrrError) << s;
  }
  nlohmann::json bound = m.toJson();
  bound["effects"]["ssgi"]["sparse_factor"] = 2.0;
  EXPECT_EQ(CostModel::fromJson(bound).effect[static_cast<size_t>(Effect::Ssgi)].sparseFactor, 2.0);
}

}  // namespace
}  // namespace mrr

namespace mrr {
namespace {

double edgeFraction(const FrameResult& f) {
  return static_cast<double>(test::countSet(f.edges.combined)) / static_cast<double>(f.edges.combined.data.size());
}

// The stress scenes model one failure each; these pin down that they do.
TEST(StressScenes, AllEdgesIsEdgesEverywhereAndTheRuleFallsBack) {
  Settings s = ssaoSettings(320, 180, 16);
  const auto off = renderScene("builtin:alledges", s);
  EXPECT_GT(edgeFraction(off.frame), 0.9);
  EXPECT_LT(off.frame.idealSpeedup, 1.1);
  s.neverSlower = true;
  const auto on = renderScene("builtin:alledges", s);
  EXPECT_TRUE(on.frame.fallback.fellBack) << "predicted " << on.frame.fallback.predictedMrrMs << " vs "
                                          << on.frame.fallback.predictedFullMs << " ms";
}

TEST(StressScenes, BumpyNormalsMultiplyTheEdges) {
  const Settings s = ssaoSettings(320, 180, 8);
  const double bumpy = edgeFraction(renderScene("builtin:bumpy", s).frame);
  const double demo = edgeFraction(renderScene("builtin:demo", s).frame);
  EXPECT_GT(bumpy, 0.4);
  EXPECT_GT(bumpy, 3.0 * demo);
}

TEST(StressScenes, WiresThinnerThanACoarsePixelAreShadedAtFullRes) {
  const auto r = renderScene("builtin:wires", ssaoSettings(320, 180, 8));
  const FrameResult& f = r.frame;
  // Rails are ~1 full-res pixel thick: their silhouettes are edges, and every edge pixel is in S_0.
  EXPECT_GT(test::countSet(f.edges.combined), 200);
  for (size_t i = 0; i < f.edges.combined.data.size(); ++i)
    if (f.edges.combined.data[i]) ASSERT_TRUE(f.levels[0].masks.stencil.data[i]);
  EXPECT_GT(f.idealSpeedup, 2.0) << "the open floor is still shaded coarsely";
}

}  // namespace
}  // namespace mrr
