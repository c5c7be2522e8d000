// The method table (common/methods.h): one row a method, and everything that names a method reads
// it. These tests loop over the rows, so a new row is checked by each of them without an edit; a
// test that leaves a row out says why.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "common/error.h"
#include "common/methods.h"
#include "common/params.h"
#include "common/stages.h"
#include "compare/bench/bench.h"
#include "frontend/frame_options.h"

namespace mrr {
namespace {

TEST(Methods, RowsAreInEnumOrderAndNamesAreUnique) {
  std::set<std::string> names;
  for (size_t i = 0; i < methods().size(); ++i) {
    const MethodInfo& m = methods()[i];
    EXPECT_EQ(static_cast<size_t>(m.mode), i) << m.name;
    EXPECT_TRUE(names.insert(std::string(m.name)).second) << m.name << " twice";
    EXPECT_EQ(&methodInfo(m.mode), &m);
    EXPECT_EQ(&parseMethod(m.name), &m);
    EXPECT_EQ(toString(m.mode), m.name);
  }
  EXPECT_EQ(parseMode("multires"), Mode::Mrr);  // an alias
  try {
    parseMethod("nope");
    FAIL() << "an unknown method was accepted";
  } catch (const MrrError& e) {
    EXPECT_NE(std::string(e.what()).find(methodNames()), std::string::npos) << e.what();  // it lists every row
  }
}

// Exactly one reference; each row's levels and mask builder agree with how it composes.
TEST(Methods, EveryRowIsConsistent) {
  int references = 0;
  for (const MethodInfo& m : methods()) {
    SCOPED_TRACE(std::string(m.name));
    references += m.reference;
    EXPECT_NE(m.shades, 0) << "shades no level";
    if (!m.userLevels) EXPECT_EQ(m.shades & ~m.levels, 0) << "shades a level it has no G-buffer for";
    EXPECT_EQ(m.findsEdges, !m.hostMadeMasks()) << "masks from edges iff it finds them";
    if (m.compose == Compose::JointBilateral) EXPECT_EQ(std::popcount(static_cast<unsigned>(m.shades)), 1) << "upsamples one level";
    if (m.aPosteriori) EXPECT_TRUE(m.blurredMasks()) << "refines blurred masks";
    for (Param p : m.params) EXPECT_TRUE(hasSettingField(p)) << optionName(p) << ": a method's parameter sets Settings";
    for (const MethodVariant& v : m.variants) {
      EXPECT_TRUE(hasSettingField(v.param)) << "+" << v.key;
      if (v.param != Param::NeverSlower && v.param != Param::Sigma2)
        EXPECT_TRUE(m.owns(v.param)) << "+" << v.key << " sets a parameter the method does not own";
    }
    // makeConstants enables and shades what the row says (the user's levels: all, by default).
    Settings s = defaultSettings(Effect::Ssao);
    s.width = 64;
    s.height = 48;
    s.mode = m.mode;
    const Constants c = makeConstants(s, 1.0f);
    for (int l = 0; l < kLevelCount; ++l) {
      const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
      const bool enabled = m.userLevels ? s.levels[static_cast<size_t>(l)].enabled : (m.levels >> l & 1u) != 0;
      EXPECT_EQ(lc.enabled, enabled) << "level " << l;
      EXPECT_EQ(lc.shaded, enabled && (m.shades >> l & 1u) != 0) << "level " << l;
    }
    EXPECT_EQ(c.neverSlower, m.neverSlower) << "the rule applies iff the row says so";
  }
  EXPECT_EQ(references, 1);
}

// A row missing from the command line's help, the bench or explore's list fails here.
TEST(Methods, EveryRowIsInTheHelpTheBenchAndExplore) {
  FrameOptions fo;
  CLI::App app;
  fo.add(app);
  const std::string help = app.get_option(optionName(Param::Method))->get_description();
  const std::vector<std::string> bench = BenchOptions{}.methods;
  const nlohmann::json rows = methodRowsJson();  // what explore's /api/info and the bench's JSON carry
  ASSERT_EQ(rows.size(), methods().size());
  for (size_t i = 0; i < methods().size(); ++i) {
    const MethodInfo& m = methods()[i];
    const std::string name(m.name);
    EXPECT_NE(help.find(" " + name + " ("), std::string::npos) << name << " is not in --method's help: " << help;
    EXPECT_NE(std::find(bench.begin(), bench.end(), name), bench.end()) << name << " is not in the bench's methods";
    EXPECT_EQ(rows[i]["name"], name);
    EXPECT_NO_THROW(settingsFor(name, Effect::Ssao, 64, 48, 16)) << name;
    for (const MethodVariant& v : m.variants) {
      // a variant that takes a number: 1, or a half where the row's range stops short of 1
      const std::string number = paramInfo(v.param).range.contains(1.0) ? "1" : "0.5";
      EXPECT_NO_THROW(settingsFor(name + "+" + std::string(v.key) + (v.value.empty() ? number : ""), Effect::Ssao, 64, 48, 16))
          << name << "+" << v.key;
    }
  }
}

// A frame file holds the parameters a method owns only for that method, and reads them back.
TEST(Methods, AFrameFileCarriesAMethodsParametersForItAlone) {
  for (const MethodInfo& m : methods()) {
    SCOPED_TRACE(std::string(m.name));
    FrameOptions fo;
    fo.mode = std::string(m.name);
    fo.size = "32x18";
    const Settings s = fo.settings();
    const nlohmann::json frame = fo.frame(nullptr, s);
    EXPECT_EQ(frame.at(std::string(paramInfo(Param::Method).key)), m.name);
    for (const FrameParamInfo& p : frameParams()) {
      if (!ownedByAMethod(p.param) || !p.frameFile) continue;
      EXPECT_EQ(frame.contains(std::string(p.key)), m.owns(p.param)) << p.key;
    }
  }
}

// A method's name, a frame parameter's option or key, and a timed stage's name are written once,
// in their tables; the code reads them from there. The scan leaves out comments (scripts,
// examples, docs and tests are not the code the rule is about). Where a word is also another
// thing's name the scan cannot tell which is meant, so it checks what it can tell:
//  - a method's name: everywhere;
//  - an option ("--tau-n") and a key of more than one word ("tau_n"): everywhere;
//  - a one-word key ("size", "effect") is also a JSON field of the reports, a GLSL uniform, a
//    subcommand's own option: not scanned;
//  - a timed name ("blend", "edges") is also a GL program's label, a tolerance rule, a shader's
//    texture: scanned only where a timing is made or read (a line with stage(, timing, Ms[ or
//    findTimed/parseTimed).
TEST(Methods, NoNameIsAStringLiteralOutsideItsTable) {
  const std::filesystem::path root = MRR_SOURCE_DIR;
  std::set<std::string> everywhere, timed;
  for (const MethodInfo& m : methods()) everywhere.insert(std::string(m.name));
  for (const FrameParamInfo& p : frameParams()) {
    everywhere.insert(optionName(p.param));
    if (p.key.find('_') != std::string_view::npos) everywhere.insert(std::string(p.key));
  }
  for (const TimedInfo& t : kTimed) timed.insert(std::string(t.name));
  const std::regex timingLine(R"(stage\(|timing|Ms\[|findTimed|parseTimed)");
  // The tables themselves.
  const std::set<std::string> tables = {"common/methods.cpp", "common/frame_params.cpp", "common/stages.h"};
  const std::regex literal("\"([^\"\\\\]*)\"");
  int files = 0;
  for (const char* dir : {"app", "common", "compare", "cpu_ref", "explore", "frontend", "gpu", "scenes"})
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root / dir)) {
      const std::string ext = entry.path().extension().string();
      if (ext != ".cpp" && ext != ".h") continue;
      const std::string rel = std::filesystem::relative(entry.path(), root).string();
      if (tables.count(rel)) continue;
      ++files;
      std::ifstream in(entry.path());
      std::string line;
      for (int number = 1; std::getline(in, line); ++number) {
        const std::string code = line.substr(0, line.find("//"));
        const bool timing = std::regex_search(code, timingLine);
        for (std::sregex_iterator it(code.begin(), code.end(), literal), end; it != end; ++it) {
          const std::string text = (*it)[1];
          if (everywhere.count(text) || (timing && timed.count(text)))
            ADD_FAILURE() << rel << ":" << number << " spells \"" << text << "\", a table's name: " << line;
        }
      }
    }
  EXPECT_GT(files, 100);  // the scan saw the code
}

}  // namespace
}  // namespace mrr
