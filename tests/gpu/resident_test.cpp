// The port's GPU-resident frame (gpu/pipeline.cpp without keepStages: what the benchmark and a
// plain render run) against the same frame with every stage read back (what compare, probe and
// --stages run, and what the parity tests check against the oracle). Both must give the same
// bits: the final image, the level map, |S_ℓ|, the shaded image and the never-slower decision.
// The resident frame keeps its images on the GPU (its block maps say where passes have work),
// counts S_ℓ and the rule's counts there, reads nothing back inside its timed frame but a few
// integers (the report's `gl` object), and blends every level in one pass (blend.frag
// FINAL_ONLY); this is the test that holds those to the checked path.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "common/cost_model.h"
#include "common/driver.h"
#include "cpu_ref/pipeline.h"
#include "gpu/pipeline.h"
#include "scenes/catalog.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

ResolvedScene builtinScene(const std::string& name) {
  SceneRequest req;
  req.scene = "builtin:" + name;
  return resolveScene(req);
}

// Small frames of an effect at few samples; the never-slower rule as given.
Settings smallFrame(Effect effect, int width, int height, bool neverSlower) {
  Settings s = defaultSettings(effect);
  s.width = width;
  s.height = height;
  s.setSamples(effect == Effect::Ssm ? 16 : 8);
  s.neverSlower = neverSlower;
  return s;
}

struct Case {
  std::string scene;
  Effect effect;
  Mode mode;
  int width, height;
  int disabledLevel;  // -1: none
  float posterior = 0.0f;  // mrr-effect's τ_v (SPEC §12.2; 0: off)
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.scene << " " << toString(c.effect) << " " << toString(c.mode) << " " << c.width << "x" << c.height;
  if (c.disabledLevel >= 0) *os << " without level " << c.disabledLevel;
  if (c.posterior > 0.0f) *os << " refined a posteriori, tau " << c.posterior;
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) {
  const Case& c = info.param;
  std::string name = c.scene + "_" + toString(c.effect) + "_" + toString(c.mode) + "_" + std::to_string(c.width) +
                     "x" + std::to_string(c.height);
  if (c.disabledLevel >= 0) name += "_noL" + std::to_string(c.disabledLevel);
  if (c.posterior > 0.0f) name += "_posterior";
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name;
}

class GpuResident : public ::testing::TestWithParam<Case> {};

TEST_P(GpuResident, GivesTheBitsOfTheFrameReadBackStageByStage) {
  MRR_REQUIRE_GL_OR_SKIP();
  const Case& k = GetParam();
  const ResolvedScene rs = builtinScene(k.scene);
  const gpu::GpuRenderer port(rs.scene);
  // small frames would fall back to full with the rule on (GpuResidentFallback covers that)
  Settings s = smallFrame(k.effect, k.width, k.height, false);
  s.mode = k.mode;
  if (k.disabledLevel >= 0) s.levels[static_cast<size_t>(k.disabledLevel)].enabled = false;
  s.effectMask.posterior = k.posterior;
  const Constants c = makeConstants(s, rs.framed.size);
  const FrameResult kept = port.render(rs.camera, c, {true, {}, nullptr});
  const FrameResult resident = port.render(rs.camera, c, {false, {}, nullptr});
  EXPECT_EQ(resident.final().data, kept.final().data) << "final image";
  EXPECT_EQ(resident.blend.levelMap.data, kept.blend.levelMap.data) << "level map";
  EXPECT_EQ(resident.shaded.data, kept.shaded.data) << "shaded image";
  EXPECT_EQ(resident.shadedPixelsTotal, kept.shadedPixelsTotal);
  // counted on the GPU after the frame (gpu/rule.h countShaded) against the host's count of the
  // stencils read back (FrameResult::countShadedPixels, countHitPixels)
  EXPECT_DOUBLE_EQ(resident.idealSpeedup, kept.idealSpeedup);
  EXPECT_DOUBLE_EQ(resident.idealSpeedupHit, kept.idealSpeedupHit);
  EXPECT_DOUBLE_EQ(resident.blockIdealSpeedup, kept.blockIdealSpeedup);
  for (size_t l = 0; l < kLevelCount; ++l) {
    EXPECT_EQ(resident.levels[l].shadedPixels, kept.levels[l].shadedPixels) << "level " << l;
    EXPECT_EQ(resident.levels[l].shadedBlockPixels, kept.levels[l].shadedBlockPixels) << "level " << l;
  }
  EXPECT_EQ(resident.fallback.fellBack, kept.fallback.fellBack);
  // The resident frame leaves the per-level images on the GPU.
  EXPECT_TRUE(resident.blend.composite[0].data.empty());
  EXPECT_TRUE(resident.levels[0].raw.data.empty());
  // A frame where finer levels show at all, or the comparison above proves little.
  if (k.mode == Mode::Mrr || k.posterior > 0.0f) {
    ASSERT_FALSE(resident.fallback.fellBack);
    int finer = 0, coarser = 0;
    for (uint8_t v : resident.blend.levelMap.data) {
      finer += v < c.coarsestEnabled;
      coarser += v > 0;
    }
    EXPECT_GT(finer, 0) << "no pixel shows a level finer than the coarsest";
    EXPECT_GT(coarser, 0) << "every pixel shows level 0";
  }
}

std::vector<Case> cases() {
  std::vector<Case> out;
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi})
    for (const MethodInfo& row : methods()) out.push_back({"demo", e, row.mode, 160, 90, -1});  // every row
  out.push_back({"demo", Effect::Ssao, Mode::Mrr, 161, 97, -1});  // odd: the padding
  out.push_back({"demo", Effect::Ssao, Mode::Mrr, 480, 270, -1});  // blocks far from any edge too
  out.push_back({"demo", Effect::Ssao, Mode::Mrr, 161, 97, 1});   // a level disabled
  out.push_back({"demo", Effect::Ssao, Mode::Mrr, 161, 97, 3});   // the coarsest disabled
  out.push_back({"shadows", Effect::Ssm, Mode::Mrr, 97, 61, 2});
  // SPEC §12: widened levels (their α reaches past the edge blocks' neighbourhood by up to the cap)
  out.push_back({"demo", Effect::Ssao, Mode::MrrEffect, 480, 270, -1});
  // SPEC §12.2: refined levels are stencilled and blended whole, also far from any edge block
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi})
    out.push_back({"demo", e, Mode::MrrEffect, 160, 90, -1, e == Effect::Ssgi ? 0.02f : 0.05f});
  out.push_back({"demo", Effect::Ssao, Mode::MrrEffect, 480, 270, -1, 0.05f});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Frames, GpuResident, ::testing::ValuesIn(cases()), caseName);

// SPEC §10/§11, docs/port.md "What a frame costs the host": every method of the table, on every
// effect, mrr-effect with its a-posteriori term (by its budget, SPEC §12.4, or by τ_v) and without,
// with a gaze and a previous frame (--pan), reads no image back inside its timed frame and at most
// a few integers (the rule's counts, 1 KB at most); the images the caller asked for come after the
// clock. A frame with keepStages reads its stages back.
struct Traffic {
  Effect effect;
  // a row of common/methods.h (mrr-effect as it comes: its term within SPEC §12.4's budget),
  // "mrr-effect+p" (its a-posteriori term by τ_v) or "mrr-effect+b0" (the a-priori masks alone)
  std::string method;
  std::string view;    // "", "gaze" or "pan"
  bool rule = true;    // the never-slower rule on (it falls back on frames this small: off too)
};

void PrintTo(const Traffic& t, std::ostream* os) {
  *os << toString(t.effect) << " " << t.method << (t.view.empty() ? "" : " " + t.view) << (t.rule ? "" : " norule");
}

std::vector<Traffic> trafficCases() {
  std::vector<Traffic> out;
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
    for (const MethodInfo& row : methods()) {
      out.push_back({e, std::string(row.name), "", true});
      if (row.neverSlower) out.push_back({e, std::string(row.name), "", false});
    }
    out.push_back({e, "mrr-effect+p", "", false});
    out.push_back({e, "mrr-effect+b0", "", false});
    for (const char* m : {"mrr", "mrr-effect", "tiles"})
      for (const char* v : {"gaze", "pan"}) out.push_back({e, m, v, false});
  }
  return out;
}

class GpuResidentTraffic : public ::testing::TestWithParam<Traffic> {};

TEST_P(GpuResidentTraffic, ReadsNoImageBackInTheTimedFrame) {
  MRR_REQUIRE_GL_OR_SKIP();
  const Traffic& t = GetParam();
  const ResolvedScene rs = builtinScene("demo");
  const gpu::GpuRenderer port(rs.scene);
  // mrr-effect as it comes: the a-posteriori term within its budget (SPEC §12.4, selected on the
  // GPU); +p: the term with τ_v alone; +b0: without the term
  const bool posterior = t.method == "mrr-effect+p", apriori = t.method == "mrr-effect+b0";
  Settings s = smallFrame(t.effect, 160, 90, t.rule);
  s.mode = parseMode(posterior || apriori ? "mrr-effect" : t.method);
  if (posterior || apriori) s.effectMask.budget = 0.0f;
  if (posterior) s.effectMask.posterior = t.effect == Effect::Ssgi ? 0.02f : 0.05f;
  if (t.view == "gaze") {
    s.foveation.gaze = true;
    s.foveation.gazeX = 100;
    s.foveation.gazeY = 40;
    s.foveation.ppd = 20.0f;
  } else if (t.view == "pan") {
    s.foveation.motion = true;
    s.foveation.panned = true;
    s.foveation.pan = 0.05f * glm::length(rs.camera.target - rs.camera.eye);
  }
  const Constants c = makeConstants(s, rs.framed.size);
  const FrameResult f = port.render(rs.camera, c, {false, {}, nullptr});
  ASSERT_TRUE(f.gl.measured);
  int budgeted = 0;
  for (const RefinementRecord& r : f.refinement) budgeted += r.budgeted ? 1 : 0;
  if (t.method == "mrr-effect" && !f.fallback.fellBack) EXPECT_GT(budgeted, 0) << "the budget did not run";
  EXPECT_EQ(f.gl.readbacks, 0) << "an image read back inside the timed frame";
  EXPECT_LE(f.gl.readbackBytes, 1024) << "more than a few integers read inside the timed frame";
  // one small read per decision of the rule at most (with the rule off it still predicts both
  // frames for the report: the same counts, SPEC §11); none for a method it does not decide
  EXPECT_LE(f.gl.countReads, 2);
  if (!methodInfo(c.mode).neverSlower) EXPECT_EQ(f.gl.countReads, 0);
  EXPECT_EQ(f.gl.waits, f.gl.countReads) << "the frame waits for its counts alone";
  EXPECT_GT(f.gl.timingWaits, 0) << "llvmpipe's wall clock waits per stage";
  // what the caller asked for (every output) came after the clock, with |S_ℓ| and the speedups
  EXPECT_GT(f.glAfterFrame.readbacks, 0);
  EXPECT_FALSE(f.final().data.empty());
  EXPECT_FALSE(f.shaded.data.empty());
  EXPECT_GT(f.shadedPixelsTotal, 0);
  if (!t.view.empty()) EXPECT_FALSE(f.levelLimit.empty());
  if (t.method == "tiles") EXPECT_FALSE(f.tileRates.empty());
  // and a frame asked for nothing but its counts reads no image at all
  RenderOptions none{false, {}, nullptr};
  none.outputs = 0;
  const FrameResult counted = port.render(rs.camera, c, none);
  EXPECT_EQ(counted.glAfterFrame.readbacks, 0);
  // |S_ℓ| and the ideal speedups; and the budget's state and counts where it ran (SPEC §12.4)
  EXPECT_LE(counted.glAfterFrame.countReads, budgeted > 0 ? 2 : 1);
  EXPECT_EQ(counted.shadedPixelsTotal, f.shadedPixelsTotal);
  EXPECT_DOUBLE_EQ(counted.idealSpeedupHit, f.idealSpeedupHit);
  EXPECT_TRUE(counted.final().data.empty());
  // the frame that keeps its stages reads them back, inside its timing
  const FrameResult kept = port.render(rs.camera, c, {true, {}, nullptr});
  EXPECT_GT(kept.gl.readbacks, 0);
}

std::string trafficName(const ::testing::TestParamInfo<Traffic>& info) {
  const Traffic& t = info.param;
  std::string name = toString(t.effect) + "_" + t.method + (t.view.empty() ? "" : "_" + t.view) + (t.rule ? "" : "_norule");
  for (char& ch : name)
    if (ch == '-' || ch == '+') ch = '_';
  return name;
}

INSTANTIATE_TEST_SUITE_P(Methods, GpuResidentTraffic, ::testing::ValuesIn(trafficCases()), trafficName);

// With the never-slower rule on and a cost model that makes shading free, the rule falls back:
// the resident frame uploads full's stencil and still gives the read-back frame's bits.
TEST(GpuResidentFallback, AFallenBackFrameGivesTheSameBits) {
  MRR_REQUIRE_GL_OR_SKIP();
  const ResolvedScene rs = builtinScene("demo");
  const gpu::GpuRenderer port(rs.scene);
  const Settings s = smallFrame(Effect::Ssao, 160, 90, true);
  CostModel model = CostModel::defaults("gpu");
  model.nsPerBlendPixel *= 1e6;  // the method's own overheads dwarf any saving
  const Constants c = makeConstants(s, rs.framed.size);
  const FrameResult kept = port.render(rs.camera, c, {true, {}, &model});
  const FrameResult resident = port.render(rs.camera, c, {false, {}, &model});
  ASSERT_TRUE(kept.fallback.fellBack);
  EXPECT_TRUE(resident.fallback.fellBack);
  EXPECT_EQ(resident.final().data, kept.final().data);
  EXPECT_EQ(resident.shadedPixelsTotal, static_cast<int64_t>(s.width) * s.height);
}

// The shadow map's target is the scene's, kept from frame to frame (GpuScene::shadowMapTarget): a
// renderer whose frames change the map's size, back and forth, gives each frame the bits a fresh
// renderer gives it, on SSM and on SSGI (its direct light reads the map too).
TEST(GpuResidentShadowMap, AKeptTargetGivesAFreshRenderersBitsAcrossSizes) {
  MRR_REQUIRE_GL_OR_SKIP();
  const ResolvedScene rs = builtinScene("shadows");
  struct Frame {
    Effect effect;
    int size;
    PixelVector<float> fresh;  // the final image from a renderer of its own
  };
  std::vector<Frame> frames;
  for (const Effect effect : {Effect::Ssm, Effect::Ssgi})
    for (const int size : {256, 512, 256}) frames.push_back({effect, size, {}});
  const auto constants = [&](const Frame& f) {
    Settings s = smallFrame(f.effect, 96, 64, false);
    s.ssm.shadowMapSize = f.size;
    return makeConstants(s, rs.framed.size);
  };
  // one renderer (one GL context) at a time: a context's display is the process's
  for (Frame& f : frames)
    f.fresh = gpu::GpuRenderer(rs.scene).render(rs.camera, constants(f), {false, {}, nullptr}).final().data;
  const gpu::GpuRenderer kept(rs.scene);
  for (const Frame& f : frames)
    EXPECT_EQ(kept.render(rs.camera, constants(f), {false, {}, nullptr}).final().data, f.fresh)
        << toString(f.effect) << ", a " << f.size << "-texel map after the frames before it";
}

// The port's rule reads the same counts as the oracle's (SPEC §11): its pixels on geometry and
// silhouettes, read back from its own G-buffer (equal to the oracle's but for silhouette pixels,
// where the rasteriser and the rays may disagree). A model where the coarse G-buffers cost more
// than shading falls back early on both paths alike.
TEST(GpuNeverSlower, CountsTheSameFrameAsTheOracle) {
  MRR_REQUIRE_GL_OR_SKIP();
  const ResolvedScene rs = builtinScene("demo");
  const gpu::GpuRenderer port(rs.scene);
  const Renderer oracle(rs.scene);
  Settings s = smallFrame(Effect::Ssao, 160, 90, false);
  const Constants c = makeConstants(s, rs.framed.size);
  const CostModel model = CostModel::defaults("gpu");
  const FrameResult p = port.render(rs.camera, c, {false, {}, &model});
  const FrameResult o = oracle.render(rs.camera, c, {false, {}, &model});
  EXPECT_GT(o.counts.hitPixels, 160 * 90 / 4);
  EXPECT_NEAR(static_cast<double>(p.counts.hitPixels), static_cast<double>(o.counts.hitPixels), 0.01 * 160 * 90);
  EXPECT_GT(o.counts.silhouette[0], 0);
  EXPECT_NEAR(static_cast<double>(p.counts.silhouette[0]), static_cast<double>(o.counts.silhouette[0]),
              0.1 * static_cast<double>(o.counts.silhouette[0]));
  EXPECT_NEAR(p.fallback.predictedFullMs, o.fallback.predictedFullMs, 0.02 * o.fallback.predictedFullMs);

  CostModel dearCopies = model;
  dearCopies.nsPerCoarseGbufferPixel = 1e6;
  s.neverSlower = true;
  const Constants on = makeConstants(s, rs.framed.size);
  const FrameResult pf = port.render(rs.camera, on, {false, {}, &dearCopies});
  const FrameResult of = oracle.render(rs.camera, on, {false, {}, &dearCopies});
  EXPECT_TRUE(pf.fallback.fellBack && pf.fallback.early);
  EXPECT_TRUE(of.fallback.fellBack && of.fallback.early);
  EXPECT_EQ(pf.shadedPixelsTotal, static_cast<int64_t>(160) * 90);
}

}  // namespace
}  // namespace mrr
