// The one tolerance table: well-formed, and looked up by stage name.
#include <gtest/gtest.h>

#include <set>

#include "common/tolerance.h"

namespace mrr {
namespace {

TEST(Tolerance, EveryRuleIsWellFormedAndExplained) {
  std::set<std::string_view> names;
  for (const ToleranceRule& r : kTolerances) {
    EXPECT_TRUE(names.insert(r.stage).second) << "duplicate rule " << r.stage;
    EXPECT_GE(r.pixelThreshold, 0.0) << r.stage;
    EXPECT_GE(r.shareOver, 0.0) << r.stage;
    EXPECT_LE(r.shareOver, 0.1) << r.stage << ": more than a tenth of pixels may differ?";
    EXPECT_GT(r.rmsBound, 0.0) << r.stage;
    EXPECT_GT(r.why.size(), 20u) << r.stage << " needs a sentence of why";
  }
}

TEST(Tolerance, LooksUpByStageAndRejectsUnknownStages) {
  EXPECT_EQ(tolerance("final").stage, "final");
  EXPECT_THROW(tolerance("no-such-stage"), std::out_of_range);
}

}  // namespace
}  // namespace mrr
