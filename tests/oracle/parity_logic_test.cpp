// The comparison behind `mrr compare` (compare/parity/parity.cpp), without a GL context: an oracle
// frame against itself, and against copies of it with one stage changed by hand. The GL runs
// of the same logic are in tests/cli (CliCompareTest, CliPlantedFaultTest).
#include <gtest/gtest.h>

#include "compare/parity/parity.h"

#include <cmath>
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

const StageRow& row(const ParityResult& r, const std::string& stage) {
  for (const StageRow& s : r.rows)
    if (s.stage == stage) return s;
  throw std::runtime_error("no row " + stage);
}

class ParityLogic : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { rendered_ = new test::Rendered(test::renderScene("builtin:demo", test::ssaoSettings(160, 96, 8))); }
  static void TearDownTestSuite() { delete rendered_; }
  static test::Rendered* rendered_;
  const FrameResult& oracle() const { return rendered_->frame; }
  const DirectionalLight& light() const { return rendered_->scene->light; }
};
test::Rendered* ParityLogic::rendered_ = nullptr;

TEST_F(ParityLogic, AFrameAgainstItselfPassesEveryStageWithZeroDifference) {
  const ParityResult r = compareFrames(oracle(), oracle(), light());
  EXPECT_TRUE(r.pass());
  EXPECT_EQ(r.firstFailing(), "");
  EXPECT_EQ(r.inherited(), 0);
  EXPECT_GT(r.rows.size(), 40u);  // every stage of every level
  for (const StageRow& s : r.rows) {
    EXPECT_EQ(s.verdict(), "PASS") << s.stage;
    // (1 − N·N of a unit float normal is within a few ulps of 0, not exactly 0.)
    const double exact = s.stage.find(".normal") != std::string::npos ? 3e-7 : 0.0;
    for (const auto* c : {&s.endToEnd, &s.sameInput})
      if (*c) EXPECT_LE((*c)->figures.maxAbs, exact) << s.stage << " " << (*c)->rule;
  }
  // Pipeline order: G-buffers first, then ... the final image, and the shaded image last.
  EXPECT_EQ(r.rows.front().stage, "gbuffer.L0.hit");
  ASSERT_GE(r.rows.size(), 2u);
  EXPECT_EQ(r.rows[r.rows.size() - 2].stage, "final");
  EXPECT_EQ(r.rows.back().stage, "shaded");
}

TEST_F(ParityLogic, AWrongEffectValueFailsAtItsLevelsRawStage) {
  FrameResult port = oracle();
  ImageF& raw = port.levels[1].raw;
  const ImageU8& s = port.levels[1].masks.stencil;
  int changed = 0;
  for (size_t i = 0; i < raw.data.size() && changed < 3; ++i)
    if (s.data[i]) raw.data[i] += 0.5f, ++changed;
  ASSERT_EQ(changed, 3);
  const ParityResult r = compareFrames(oracle(), port, light());
  EXPECT_FALSE(r.pass());
  EXPECT_EQ(r.firstFailing(), "raw.L1");
  EXPECT_EQ(row(r, "raw.L1").verdict(), "FAIL");
  EXPECT_EQ(row(r, "raw.L1").sameInput->figures.over, 3);
  EXPECT_EQ(row(r, "raw.L0").verdict(), "PASS");
}

TEST_F(ParityLogic, AStencilPixelFlippedOutsideTheGuardBandFails) {
  FrameResult port = oracle();
  ImageU8& s = port.levels[2].masks.stencil;
  const ImageF& a = port.levels[2].masks.alpha;
  size_t flip = s.data.size();
  for (size_t i = 0; i < s.data.size() && flip == s.data.size(); ++i)
    if (!s.data[i] && a.data[i] == 0.0f) flip = i;  // far from the cutoff a > 0
  ASSERT_LT(flip, s.data.size());
  s.data[flip] = 1;
  const ParityResult r = compareFrames(oracle(), port, light());
  EXPECT_EQ(r.firstFailing(), "stencil.L2");
  EXPECT_EQ(row(r, "stencil.L2").sameInput->figures.over, 1);
  EXPECT_GE(row(r, "stencil.L2").sameInput->figures.band, 0);
}

TEST_F(ParityLogic, ABlendDifferenceIsBlamedOnItsStepAndInheritedAfter) {
  FrameResult port = oracle();
  ImageF& up = port.blend.upsampled[2];
  for (float& v : up.data) v *= 0.5f;  // every ĉ_2 halved: an upsampling bug
  const ParityResult r = compareFrames(oracle(), port, light());
  EXPECT_EQ(r.firstFailing(), "upsample.L2");
  // c'_2 = α ĉ_2 + (1 − α) c'_3 was computed from the correct ĉ_2, so on the port's own
  // (halved) ĉ_2 it no longer matches: the composite step is flagged too, but after.
  EXPECT_EQ(row(r, "upsample.L1").verdict(), "PASS");
  EXPECT_EQ(row(r, "final").verdict(), "PASS");  // the final image itself was not touched
}

TEST_F(ParityLogic, ADifferenceOnlyEndToEndIsUpstreamAndDoesNotFail) {
  // The port's final differs from the oracle's, but it equals its own finest composite: the
  // final row is UPSTREAM (inherited), and the frame still passes.
  FrameResult port = oracle();
  for (float& v : port.blend.final.data) v = std::min(1.0f, v + 0.1f);
  for (float& v : port.blend.composite[0].data) v = std::min(1.0f, v + 0.1f);
  const ParityResult r = compareFrames(oracle(), port, light());
  EXPECT_EQ(row(r, "final").verdict(), "UPSTREAM");
  EXPECT_EQ(row(r, "composite.L0").verdict(), "FAIL");  // the change itself is caught where it is
  EXPECT_EQ(r.firstFailing(), "composite.L0");
}

TEST_F(ParityLogic, TheTableNamesTheFirstFailingStage) {
  FrameResult port = oracle();
  port.levels[0].raw.data[0] += 1.0f;
  port.levels[0].masks.stencil.data[0] = 1;
  const std::string table = formatParityTable(compareFrames(oracle(), port, light()));
  // The verdict names the stage and the port's shader that computes it.
  EXPECT_NE(table.find("FAIL: first failing stage raw.L0 (ssao.frag)"), std::string::npos) << table;
  EXPECT_NE(table.find("stage"), std::string::npos);
}

TEST(ParityShaders, EachStageNamesTheFileThatComputesIt) {
  ParityResult r;
  r.effect = Effect::Ssm;
  EXPECT_EQ(r.shaderOf("raw.L0"), "ssm.frag");  // one file per effect: the frame's
  EXPECT_EQ(r.shaderOf("edges.depth"), "edges.frag");
  EXPECT_EQ(r.shaderOf("gbuffer.L1.normal"), "gbuffer.frag");
  EXPECT_EQ(r.shaderOf("final"), "blend.frag");
  EXPECT_EQ(r.shaderOf("never_slower"), "");  // no part, no shader
}

// Every figure of a check is over the same pixels: a difference in the guard band is counted
// apart and moves neither the RMS nor max |Δ| (before, the RMS took the band and max |Δ| did
// not, so a row could read "max|d| 2.38e-07, rms 0.014").
TEST(ParityFigures, RmsAndMaxAreOverTheSamePixels) {
  ImageF a(4, 1, 1, 0.0f), b(4, 1, 1, 0.0f);
  b.data = {0.01f, 0.0f, 0.5f, 0.0f};
  const std::vector<char> band = {0, 0, 1, 0};
  const DiffFigures f = diffImages(a, b, 0.1, {}, &band);
  EXPECT_EQ(f.pixels, 3);
  EXPECT_EQ(f.overInBand, 1);
  EXPECT_EQ(f.over, 0);
  EXPECT_NEAR(f.maxAbs, 0.01, 1e-9);
  EXPECT_NEAR(f.rms, 0.01 / std::sqrt(3.0), 1e-9);
  EXPECT_LE(f.rms, f.maxAbs);
}

// UPSTREAM names what it inherits: the earlier rows that let pixels through within their own
// rules, with where each is worst (to probe).
TEST(ParityUpstream, AnUpstreamRowNamesWhereItsDifferenceCameFrom) {
  ParityResult r;
  auto check = [](int64_t over, int64_t inBand, bool pass, int x, int y) {
    StageCheck c;
    c.rule = "final";
    c.pass = pass;
    c.figures.pixels = 100;
    c.figures.over = over;
    c.figures.overInBand = inBand;
    c.figures.maxAbs = over > 0 ? 0.2 : 0.0;
    c.figures.worstX = x;
    c.figures.worstY = y;
    return c;
  };
  r.rows.push_back({"edges", -1, 1, check(0, 2, true, -1, -1), std::nullopt});
  r.rows.push_back({"raw.L0", 0, 1, check(1, 0, true, 111, 74), std::nullopt});
  r.rows.push_back({"sub.L0", 0, 1, check(0, 0, true, -1, -1), std::nullopt});
  r.rows.push_back({"final", -1, 1, check(40, 0, false, 111, 74), check(0, 0, true, -1, -1)});
  ASSERT_EQ(r.rows.back().verdict(), "UPSTREAM");
  EXPECT_EQ(r.inheritedFrom(3), "edges (2 px differ in its guard band); raw.L0 (1 px over its threshold, worst at 111,74)");
  const std::string table = formatParityTable(r);
  EXPECT_NE(table.find("UPSTREAM final: inherits what earlier stages let through: edges"), std::string::npos) << table;
  EXPECT_EQ(r.inheritedFrom(1), "edges (2 px differ in its guard band)");
}

}  // namespace
}  // namespace mrr
