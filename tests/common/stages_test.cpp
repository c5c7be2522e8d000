// The stage list (common/stages.h): every rule it names is in the tolerance table, and every
// name it makes is read back as its own part. The timed stages: every name read back as its row,
// and a name the list does not know an error, in the list and in the never-slower rule's sums.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

#include "common/error.h"
#include "common/stages.h"
#include "common/tolerance.h"
#include "compare/rule/rule.h"

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
    EXPECT_FALSE(timedInfo(p.stage).name.empty()) << p.name;
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

TEST(TimedStages, EveryNameReadsBackAsItsRowAndLevel) {
  std::set<std::string> names;
  for (const TimedInfo& t : kTimed) {
    for (int level = t.perLevel ? 0 : -1; level < (t.perLevel ? kLevelCount : 0); ++level) {
      const std::string name = timedName(t.timed, level);
      EXPECT_TRUE(names.insert(name).second) << "two rows make " << name;
      const TimedStage back = parseTimed(name);
      EXPECT_EQ(back.timed, t.timed) << name;
      EXPECT_EQ(back.level, level) << name;
      EXPECT_EQ(back.cost(), level == 0 ? t.costAtLevel0 : t.cost) << name;
    }
    EXPECT_GT(t.what.size(), 10u) << t.name << " needs a line of what it times";
  }
  EXPECT_EQ(timedName(Timed::GBuffer, 2), "gbuffer.L2");
  EXPECT_EQ(timedName(Timed::Rule), "rule");
  EXPECT_EQ(stageName(Part::Raw, 1), timedName(Timed::Effect, 1));
  // The accounts compare/rule/rule.cpp sums (SPEC §11): the full-res G-buffer is paid before the
  // decision by every mode, a coarse level's is the method's rest (g).
  EXPECT_EQ(parseTimed("gbuffer.L0").cost(), CostClass::Shared);
  EXPECT_EQ(parseTimed("gbuffer.L1").cost(), CostClass::Rest);
  EXPECT_EQ(parseTimed("planes.L0").cost(), CostClass::LevelPixel);
  EXPECT_EQ(parseTimed("bilateral.L3").cost(), CostClass::Shading);
  EXPECT_EQ(parseTimed("masks").cost(), CostClass::Detection);
  EXPECT_EQ(parseTimed("stencils").info().on, TimedOn::Port);
}

TEST(TimedStages, ANameTheListDoesNotKnowIsAnError) {
  for (const char* name : {"effects.L0", "effect", "effect.L9", "effect.L0.x", "rule.L0", "gbuffer.l0", "", "masks2"}) {
    EXPECT_FALSE(findTimed(name).has_value()) << name;
    EXPECT_THROW(parseTimed(name), MrrError) << name;
  }
  try {
    parseTimed("occluders.L1");
    FAIL() << "no error";
  } catch (const MrrError& e) {
    EXPECT_NE(std::string(e.what()).find("'occluders.L1' is not in the stage list"), std::string::npos) << e.what();
  }
}

// The never-slower rule's sums read the classes: a stage renamed on one side (here "planes.L0"
// as "occluders.L0") is an error, not a term that reads 0.
TEST(TimedStages, TheRuleSumsByClassAndRefusesAnUnknownName) {
  std::map<std::string, double> ms = {{"gbuffer.L0", 1.0}, {"gbuffer.L1", 2.0}, {"planes.L0", 4.0}, {"effect.L0", 8.0},
                                      {"bilateral.L0", 16.0}, {"edges", 32.0}, {"masks", 64.0}, {"total", 256.0}};
  EXPECT_EQ(costClassMs(ms, CostClass::Shared), 1.0);
  EXPECT_EQ(costClassMs(ms, CostClass::Rest), 2.0);
  EXPECT_EQ(costClassMs(ms, CostClass::LevelPixel), 4.0);
  EXPECT_EQ(costClassMs(ms, CostClass::Shading), 24.0);
  EXPECT_EQ(costClassMs(ms, CostClass::Detection), 96.0);
  EXPECT_EQ(costClassMs(ms, CostClass::Total), 256.0);
  ms.erase("planes.L0");
  ms["occluders.L0"] = 4.0;
  EXPECT_THROW(costClassMs(ms, CostClass::LevelPixel), MrrError);
  EXPECT_THROW(costClassMs(ms, CostClass::Shading), MrrError) << "whichever class is asked for";
}

}  // namespace
}  // namespace mrr
