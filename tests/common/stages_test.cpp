// The stage list (common/stages.h): every rule it names is in the tolerance table, and every
// name it makes is read back as its own part.
#include <gtest/gtest.h>

#include <string>

#include "common/stages.h"
#include "common/tolerance.h"

namespace mrr {
namespace {

bool isRule(std::string_view name) {
  for (const ToleranceRule& r : kTolerances)
    if (r.stage == name) return true;
  return false;
}

TEST(StageList, EveryRuleItNamesIsInTheToleranceTable) {
  for (const PartInfo& p : kParts)
    for (std::string_view rule : {p.endToEnd, p.sameInput}) {
      if (rule.empty()) continue;
      if (rule.substr(0, 8) == "<effect>") {  // one rule per effect
        for (const char* effect : {"ssao", "ssm", "ssgi"})
          EXPECT_TRUE(isRule(std::string(effect) + std::string(rule.substr(8)))) << p.name << ": " << rule;
      } else if (rule == "gbuffer.*") {  // one rule per G-buffer channel
        for (const char* channel : {"hit", "depth", "normal", "albedo"})
          EXPECT_TRUE(isRule(std::string("gbuffer.") + channel)) << p.name;
      } else {
        EXPECT_TRUE(isRule(rule)) << p.name << ": no tolerance rule " << rule;
      }
    }
}

TEST(StageList, NamesReadBackAsTheirParts) {
  for (const PartInfo& p : kParts) {
    Part back{};
    ASSERT_TRUE(partOf(partName(p.part, 2), back)) << p.name;
    EXPECT_EQ(back, p.part) << p.name;
    EXPECT_EQ(partName(p.part, 2), std::string(p.name) + (p.perLevel ? ".L2" : "")) << p.name;
    EXPECT_FALSE(p.stage.empty()) << p.name;
    EXPECT_FALSE(p.shader.empty()) << p.name;
  }
  Part part{};
  ASSERT_TRUE(partOf("gbuffer.L0.depth", part));  // compare's rows add a channel or edge kind
  EXPECT_EQ(part, Part::GBuffer);
  ASSERT_TRUE(partOf("edges.normal", part));
  EXPECT_EQ(part, Part::Edges);
  EXPECT_FALSE(partOf("fallback", part));  // a decision, not an image
  EXPECT_EQ(stageName(Part::Raw, 1), "effect.L1");
  EXPECT_EQ(stageName(Part::Stencil), "masks");
}

}  // namespace
}  // namespace mrr
