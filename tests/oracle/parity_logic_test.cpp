// The comparison behind `mrr compare` (compare/parity.cpp), without a GL context: an oracle
// frame against itself, and against copies of it with one stage changed by hand. The GL runs
// of the same logic are in tests/cli (CliCompareTest, CliPlantedFaultTest).
#include <gtest/gtest.h>

#include "compare/parity.h"
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
  EXPECT_NE(table.find("FAIL: first failing stage "), std::string::npos) << table;
  EXPECT_NE(table.find("stage"), std::string::npos);
}

}  // namespace
}  // namespace mrr
