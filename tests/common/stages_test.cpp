// The stage list (common/stages.h): every rule it names is in the tolerance table, and every
// name it makes is read back as its own part; every row carries its image's accessor, a caption
// and a display, and inputs that name parts of the list (the accessors on real frames:
// tests/oracle/stage_images_test.cpp). The timed stages: every name read back as its row,
// and a name the list does not know an error, in the list and in the never-slower rule's sums.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <string>

#include "common/error.h"
#include "common/stage_images.h"
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

// A row without its accessor (or with one missing a function), a caption or a display fails here.
TEST(StageList, EveryRowCarriesItsAccessorCaptionAndDisplay) {
  const std::set<Display> bespoke = {Display::GBuffer, Display::ShadowMap, Display::Edges};
  for (const PartInfo& p : kParts) {
    ASSERT_NE(p.image, nullptr) << p.name << ": no accessor (common/stage_images.cpp)";
    EXPECT_NE(p.image->holds, nullptr) << p.name;
    EXPECT_NE(p.image->read, nullptr) << p.name;
    EXPECT_NE(p.image->write, nullptr) << p.name;
    EXPECT_GT(p.view.caption.size(), 8u) << p.name << " needs a caption";
    const int display = static_cast<int>(p.view.display);
    EXPECT_TRUE(display >= static_cast<int>(Display::Binary) && display <= static_cast<int>(Display::Edges)) << p.name;
    // The bespoke multi-channel views are the G-buffer's, the shadow map's and the edges' own.
    EXPECT_EQ(bespoke.count(p.view.display) > 0,
              p.part == Part::GBuffer || p.part == Part::ShadowMap || p.part == Part::Edges) << p.name;
    EXPECT_LT(p.view.channel, static_cast<int>(partChannels(p.part).size())) << p.name << ": shows a channel it lacks";
    if (p.view.display == Display::Scalar) EXPECT_LT(p.view.lo, p.view.hi) << p.name << ": a scalar's ramp";
    EXPECT_NE(viewCaption(p.part, 1).find(std::string(p.view.caption)), std::string::npos) << p.name;
    EXPECT_TRUE(p.grid == Grid::Level || !p.perLevel || p.step == 5)
        << p.name << ": a per-level part off its level's grid (only the blend's are at full res)";
    // Nothing held by a frame that holds nothing.
    const FrameResult empty;
    EXPECT_FALSE(p.image->holds(empty, 0)) << p.name;
    EXPECT_TRUE(p.image->read(empty, 0).empty()) << p.name;
  }
  EXPECT_EQ(viewCaption(Part::Stencil, 1), "the stencil S_ℓ: shaded at this level: 1 white, 0 black");
  EXPECT_EQ(viewCaption(Part::Final, 3), "the final effect buffer (RGB), clamped to [0, 1]: 0 black, 1 white");
  EXPECT_EQ(viewCaption(Part::Eccentricity, 1), "eccentricity from the gaze (degrees) on the ramp over [0, 30]");
}

// Every input names a part of the list at a level it has; a row with a same-input rule reads
// something, a row reads nothing at its own level of itself, and the names resolve per frame.
TEST(StageList, EveryInputNamesAPartThatExists) {
  for (const PartInfo& p : kParts) {
    EXPECT_LE(p.inputs.count, PartInputs::kMax) << p.name;
    if (!p.sameInput.empty()) EXPECT_FALSE(p.inputs.empty()) << p.name << ": a same-input check that reads nothing";
    for (const PartInput& in : p.inputs) {
      ASSERT_GE(static_cast<int>(in.part), 0) << p.name;
      ASSERT_LT(static_cast<size_t>(in.part), std::size(kParts)) << p.name << ": an input outside the list";
      const PartInfo& input = partInfo(in.part);
      EXPECT_FALSE(in.part == p.part && in.level == InputLevel::Same) << p.name << " reads itself";
      if (in.level == InputLevel::NextCoarser || in.level == InputLevel::Coarser)
        EXPECT_TRUE(p.perLevel && input.perLevel) << p.name << " reads " << input.name << " at a coarser level";
      if (in.level == InputLevel::Zero || in.level == InputLevel::Every)
        EXPECT_TRUE(input.perLevel) << p.name << " reads " << input.name << " at a level it does not have";
    }
  }
  // Resolved on a frame: mode mrr-effect SSM with level 1 disabled, foveated.
  Settings s = defaultSettings(Effect::Ssm);
  s.mode = Mode::MrrEffect;
  s.levels[1].enabled = false;
  s.foveation.gaze = true;
  Constants c = makeConstants(s, 1.0f);
  ASSERT_EQ(c.nextCoarserEnabled(0), 2);
  using Names = std::vector<std::string>;
  EXPECT_EQ(partInputNames(Part::Marks, 0, c), (Names{"sub.L2", "stencil.L2", "gbuffer.L2", "levellimit"}));
  EXPECT_EQ(partInputNames(Part::Marks, 3, c), (Names{"levellimit"}));  // the coarsest has no coarser level
  EXPECT_EQ(partInputNames(Part::Edges, -1, c), (Names{"gbuffer.L0", "shadowtest"}));
  EXPECT_EQ(partInputNames(Part::Stencil, 2, c),
            (Names{"edges", "levellimit", "tilerates", "marks.L2", "gbuffer.L0", "shadowmap"}));
  EXPECT_EQ(partInputNames(Part::Composite, 1, c),
            (Names{"upsample.L1", "blendalpha.L1", "composite.L2", "composite.L3"}));
  EXPECT_EQ(partInputNames(Part::Raw, 2, c), (Names{"gbuffer.L2", "stencil.L2", "shadowmap"}));
  // SSGI's edges do not read its shadow test; mrr's masks read no footprint; tiles compose as a peer.
  s.effect = Effect::Ssgi;
  s.mode = Mode::Mrr;
  c = makeConstants(s, 1.0f);
  EXPECT_EQ(partInputNames(Part::Edges, -1, c), (Names{"gbuffer.L0"}));
  EXPECT_EQ(partInputNames(Part::Stencil, 0, c), (Names{"edges", "levellimit", "tilerates", "marks.L0"}));
  EXPECT_EQ(partInputNames(Part::Final, -1, c).size(), 2u * kLevelCount);
  s.mode = Mode::Tiles;
  c = makeConstants(s, 1.0f);
  EXPECT_EQ(partInputNames(Part::Final, -1, c).size(), 3u * kLevelCount + 1);
}

// README's output-files table lists every part of the stages EXR, in the list's order, with its channels.
TEST(StageList, TheReadmesPartTableListsEveryRow) {
  std::ifstream readme(std::string(MRR_SOURCE_DIR) + "/README.md");
  ASSERT_TRUE(readme) << "README.md";
  std::string line;
  while (std::getline(readme, line) && line.rfind("| part | channels | what |", 0) != 0) {}
  ASSERT_TRUE(readme) << "README.md has no part table";
  std::getline(readme, line);  // |---|
  std::vector<std::pair<std::string, std::string>> rows;  // name (without .Lℓ), channels cell
  while (std::getline(readme, line) && line.rfind("| `", 0) == 0) {
    const size_t end = line.find('`', 3);
    std::string name = line.substr(3, end - 3);
    if (const size_t level = name.find(".L"); level != std::string::npos) name.resize(level);
    const size_t cell = line.find('|', end);
    rows.emplace_back(name, line.substr(cell, line.find('|', cell + 1) - cell));
  }
  ASSERT_EQ(rows.size(), std::size(kParts));
  for (size_t i = 0; i < rows.size(); ++i) {
    const PartInfo& p = kParts[i];
    EXPECT_EQ(rows[i].first, p.name) << "row " << i;
    for (const std::string& channel : partChannels(p.part)) {  // "P.x" may be written "P.x/y/z"
      const size_t dot = channel.find('.');
      const std::string head = dot == std::string::npos ? "`" + channel + "`" : channel.substr(0, dot + 1);
      EXPECT_NE(rows[i].second.find(head), std::string::npos) << p.name << ": channel " << channel;
    }
  }
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
