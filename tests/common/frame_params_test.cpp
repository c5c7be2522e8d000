// The frame-parameter table (common/frame_params.h) and what it drives: the command line's options
// (frontend/frame_options.cpp), frame files (frontend/frame_file.cpp), the help text, and the one
// factory that picks a path (frontend/renderers.h). A parameter is one row, its name a
// string in one source file.
#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "common/error.h"
#include "common/frame_params.h"
#include "common/methods.h"
#include "frontend/frame_file.h"
#include "frontend/frame_options.h"
#include "frontend/renderers.h"
#include "scenes/catalog.h"

namespace mrr {
namespace {

TEST(FrameParams, EveryRowIsAnOptionOfEveryFrameCommand) {
  FrameOptions fo;
  CLI::App app;
  fo.add(app);
  for (const FrameParamInfo& p : frameParams()) {
    const std::string option = optionName(p.param);
    EXPECT_NE(app.get_option_no_throw(option), nullptr) << option;
    EXPECT_EQ(findParam(option), &p);
    EXPECT_EQ(findParam(p.key), &p);
  }
  EXPECT_EQ(findParam("--mode"), &paramInfo(Param::Method));  // an alias
  EXPECT_EQ(findParam("-q"), &paramInfo(Param::Quiet));
  EXPECT_EQ(findParam("--no-such-thing"), nullptr);
  // CLI11 registered exactly the table's rows (and its own --help).
  EXPECT_EQ(app.get_options().size(), frameParams().size() + 1);
}

TEST(FrameParams, TheHelpShowsTheDefaultsTheCodeHolds) {
  // Typed once, in Settings: the help is generated from it, not written beside it.
  const Settings s = defaultSettings(Effect::Ssao);
  std::ostringstream tauN;
  tauN << s.edges.normalThreshold;
  EXPECT_NE(paramHelp(Param::TauN).find("default " + tauN.str()), std::string::npos) << paramHelp(Param::TauN);
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi})
    EXPECT_NE(paramHelp(Param::Samples).find(toString(e) + " " + std::to_string(defaultSettings(e).samples())),
              std::string::npos)
        << paramHelp(Param::Samples);
  EXPECT_NE(paramHelp(Param::ShadowMapSize).find(std::to_string(s.ssm.shadowMapSize)), std::string::npos);
  EXPECT_NE(paramHelp(Param::Size, "1280x720").find("default 1280x720"), std::string::npos);
}

TEST(FrameParams, AFrameFileHoldsExactlyTheRowsMarkedForIt) {
  FrameOptions fo;
  fo.size = "64x36";
  fo.flipUp = true;  // flip_up is written only when chosen
  fo.set(Param::Seed, "5");  // seed only when not 0 (mrr's own sampling)
  fo.coarseGBuffer = "render";  // coarse_gbuffer only when not subsample
  fo.gaze = "3,4";   // so are the gaze and foveate
  fo.mode = "mrr-effect";  // and mrr-effect's widening, a-posteriori term and ablation arm (effect_*)
  fo.pan = 0.25f;          // and the pan, when not 0
  const ResolvedScene rs = resolveScene(fo.sceneRequest());
  const nlohmann::json frame = fo.frame(rs, fo.settings());
  std::set<std::string> expected = {"mrr_frame"};
  for (const FrameParamInfo& p : frameParams()) {  // prev_frame names a file: written only when given
    bool otherMethods = false;  // a parameter another method owns is in that method's files only
    for (const MethodInfo& m : methods()) otherMethods |= m.mode != Mode::MrrEffect && m.owns(p.param);
    if (p.frameFile && p.param != Param::PrevFrame && !otherMethods) expected.insert(std::string(p.key));
  }
  std::set<std::string> written;
  for (const auto& [key, value] : frame.items()) written.insert(key);
  EXPECT_EQ(written, expected);
  // And it reads back: one word per row, less mrr_frame, disable_level (no level disabled),
  // ao_texel_depth and effect_only (flags left off).
  const std::vector<std::string> words = frameArgs(frame, "test");
  EXPECT_EQ(words.size(), expected.size() - 4);
  // A key no row has is refused, naming the keys a frame has.
  nlohmann::json bad = frame;
  bad["tau_x"] = 1;
  try {
    frameArgs(bad, "test");
    FAIL() << "an unknown key was accepted";
  } catch (const MrrError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown key \"tau_x\""), std::string::npos) << e.what();
  }
}

TEST(FrameParams, PerLevelValuesAreSplitByTheCommandLineAndChecked) {
  FrameOptions fo;
  CLI::App app;
  fo.add(app);
  app.parse(std::vector<std::string>{"--sigma2=1,2,3,4"});
  EXPECT_EQ(*fo.value(Param::Sigma2), "1,2,3,4");
  EXPECT_EQ(fo.settings().levels[2].sigma2, 3.0f);
  fo.set(Param::Sigma2, "1,2,3");
  EXPECT_THROW(fo.settings(), MrrError);
  fo.set(Param::Sigma2, "1,2,65,4");
  try {
    fo.settings();
    FAIL() << "sigma2 65 was accepted";
  } catch (const MrrError& e) {
    EXPECT_EQ(std::string(e.what()), "--sigma2 1,2,65,4: level 2's value must be in [0, 64]");
  }
}

// The front-end layers take every multi-word parameter name from the table: none of them is a
// string literal in app/, frontend/ or explore/ code (comments aside).
TEST(FrameParams, NoFrontEndFileSpellsAParameterName) {
  const std::filesystem::path root = MRR_SOURCE_DIR;
  for (const char* dir : {"app", "frontend", "explore"})
    for (const auto& entry : std::filesystem::directory_iterator(root / dir)) {
      const std::string ext = entry.path().extension().string();
      if (ext != ".cpp" && ext != ".h") continue;
      std::ifstream in(entry.path());
      std::string code, line;
      while (std::getline(in, line)) code += line.substr(0, line.find("//")) + "\n";
      for (const FrameParamInfo& p : frameParams()) {
        const std::string key(p.key);
        if (key.find('_') == std::string::npos) continue;  // one-word keys ("size") are also other things' names
        EXPECT_EQ(code.find("\"" + key + "\""), std::string::npos) << entry.path() << " spells " << key;
        EXPECT_EQ(code.find("\"" + optionName(p.param)), std::string::npos) << entry.path() << " spells " << optionName(p.param);
      }
    }
}

TEST(Renderers, ThePathIsChosenInOnePlace) {
  const ResolvedScene rs = resolveScene(SceneRequest{});
  const auto oracle = makeRenderer("cpu", rs.scene);
  EXPECT_STREQ(oracle->path(), "cpu");
  EXPECT_EQ(oracle->timingMethod(), "");
  try {
    makeRenderer("tpu", rs.scene);
    FAIL() << "an unknown path was accepted";
  } catch (const MrrError& e) {
    EXPECT_EQ(std::string(e.what()), "--path tpu: unknown path (expected cpu or gpu)");
  }
}

}  // namespace
}  // namespace mrr
