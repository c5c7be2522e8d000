// The port's GPU-resident frame (gpu/pipeline.cpp without keepStages: what the benchmark and a
// plain render run) against the same frame with every stage read back (what compare, probe and
// --stages run, and what the parity tests check against the oracle). Both must give the same
// bits: the final image, the level map, |S_ℓ|, the shaded image and the never-slower decision.
// The resident frame keeps its images on the GPU, reads back only S_ℓ, and blends every level
// in one pass (blend.frag FINAL_ONLY); this is the test that holds those to the checked path.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "common/cost_model.h"
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
