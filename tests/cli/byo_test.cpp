// Bring your own: `mrr shaders export`, `--shaders DIR` (the port with a user's
// GLSL) and `compare --against FILE` (another renderer's stages), run through the real binary.
// Each test edits a shader or a stage the way a user's bug would and checks the verdict and the
// stage `compare` names on its last line. Frames are small (160x90 or less, few samples).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/image_io.h"
#include "tests/cli/run_mrr.h"
#include "tests/test_support.h"

namespace mrr {
namespace {
namespace fs = std::filesystem;

using cli::lastLine;
using cli::mrr;
using cli::quote;
using cli::Ran;
using cli::with;

void writeText(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// `text` with `find` replaced by `replace` (the test fails when `find` is not there).
std::string edited(const std::string& text, const std::string& find, const std::string& replace) {
  const size_t at = text.find(find);
  EXPECT_NE(at, std::string::npos) << "the shader no longer holds: " << find;
  if (at == std::string::npos) return text;
  return text.substr(0, at) + replace + text.substr(at + find.size());
}

// Exports the shaders into DIR/shaders and keeps only `keep` (all when empty).
std::string exportShaders(const std::string& dir, const std::vector<std::string>& keep = {}) {
  const std::string shaders = (fs::path(dir) / "shaders").string();
  const Ran r = mrr({"shaders", "export", shaders}, dir);
  EXPECT_EQ(r.status, 0) << r.err;
  if (!keep.empty())
    for (const auto& e : fs::directory_iterator(shaders)) {
      const std::string name = e.path().filename().string();
      if (name != "README.md" && std::find(keep.begin(), keep.end(), name) == keep.end()) fs::remove_all(e.path());
    }
  return shaders;
}

// The same words less -q: the progress lines (and the "[mrr] shaders from" line) come back.
std::vector<std::string> loud(std::vector<std::string> args) {
  args.erase(std::remove(args.begin(), args.end(), "-q"), args.end());
  return args;
}

std::vector<std::string> compareArgs(const std::string& effect, const std::vector<std::string>& extra) {
  std::vector<std::string> args = {"compare", "--scene", "builtin:demo", "--effect", effect, "--size", "160x90",
                                   "--samples", effect == "ssao" ? "8" : "16", "-q"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

TEST(ShadersExport, WritesEveryShaderAndAReadme) {
  const std::string dir = test::scratchDir();
  const std::string shaders = exportShaders(dir);
  for (const char* f : {"ssao.frag", "blend.frag", "common.glsl", "bilateral.glsl", "shadowmap.glsl", "fullscreen.vert",
                        "README.md"})
    EXPECT_TRUE(fs::exists(fs::path(shaders) / f)) << f;
  EXPECT_NE(test::readFile((fs::path(shaders) / "README.md").string()).find("docs/shader-contract.md"), std::string::npos);
}

// Exported and loaded unchanged: every file comes from DIR, and every effect passes.
TEST(ShadersDir, UnchangedExportPassesEveryEffect) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir);
  const Ran r = mrr(loud(compareArgs("all", {"--shaders", shaders})), dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("[mrr] shaders from " + shaders + ": albedo.glsl, bilateral.frag, bilateral.glsl, blend.frag"), std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;  // README.md is not a stray file
  EXPECT_EQ(lastLine(r.out).rfind("PASS", 0), 0u) << r.out;
}

// Exported unchanged, the port computes the same bits as with its built-in shaders.
TEST(ShadersDir, UnchangedExportRendersTheSameStages) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir);
  for (const std::string effect : {"ssao", "ssm", "ssgi"}) {
    std::vector<std::vector<ExrPart>> frames;
    for (const bool own : {false, true}) {
      const std::string file = (fs::path(dir) / (effect + (own ? "-own.exr" : "-builtin.exr"))).string();
      std::vector<std::string> args = {"render", "--scene", "builtin:boxes", "--path", "gpu", "--effect", effect,
                                       "--size", "96x54", "--samples", "16", "--shadow-map-size", "512", "-q",
                                       "--stages", file};
      if (own) args.insert(args.end(), {"--shaders", shaders});
      const Ran r = mrr(args, dir);
      ASSERT_EQ(r.status, 0) << r.err;
      frames.push_back(readParts(file));
    }
    ASSERT_EQ(frames[0].size(), frames[1].size()) << effect;
    for (size_t i = 0; i < frames[0].size(); ++i)
      EXPECT_TRUE(frames[0][i].image.data == frames[1][i].image.data) << effect << ": " << frames[0][i].name;
  }
}

// An output scaled by a few per cent: the stage that was edited fails, and is named last.
TEST(ShadersDir, ScaledSsaoOutputFailsAtRaw) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir, {"ssao.frag"});
  const fs::path file = fs::path(shaders) / "ssao.frag";
  writeText(file, edited(test::readFile(file.string()), "ao = vec4(1.0 - occlusion / float(samples), 0.0, 0.0, 1.0);",
                         "ao = vec4((1.0 - occlusion / float(samples)) * 0.97, 0.0, 0.0, 1.0);"));
  const Ran r = mrr(compareArgs("ssao", {"--shaders", shaders}), dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_EQ(r.err.find("shaders from"), std::string::npos) << "-q is quiet:\n" << r.err;
  EXPECT_EQ(lastLine(r.out).rfind("FAIL: first failing stage raw.L", 0), 0u) << r.out;
  EXPECT_NE(lastLine(r.out).find("(ssao.frag)"), std::string::npos) << r.out;
}

// An upsampling tap off by half a level pixel: the blend fails at the upsample.
TEST(ShadersDir, HalfPixelTapFailsAtUpsample) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir, {"blend.frag"});
  const fs::path file = fs::path(shaders) / "blend.frag";
  writeText(file, edited(test::readFile(file.string()), "vec2 u = vec2(p - scale / 2) / float(scale);",
                         "vec2 u = vec2(p) / float(scale);"));
  const Ran r = mrr(compareArgs("ssao", {"--shaders", shaders}), dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out).rfind("FAIL: first failing stage upsample.L", 0), 0u) << r.out;
}

// A syntax error: FILE:LINE and exit 2, in the stage file and in an include.
TEST(ShadersDir, SyntaxErrorGivesFileAndLine) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir, {"ssao.frag"});
  const fs::path file = fs::path(shaders) / "ssao.frag";
  const std::string text = test::readFile(file.string());
  // line 16 is the blank line after the last declaration
  std::istringstream lines(text);
  std::string out, line;
  for (int n = 1; std::getline(lines, line); ++n) out += (n == 16 ? "float broken = ;" : line) + "\n";
  writeText(file, out);
  Ran r = mrr(compareArgs("ssao", {"--shaders", shaders}), dir);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(r.err.find("mrr: error: " + (fs::path(shaders) / "ssao.frag").string() + ":16: "), r.err.find("mrr: error:"))
      << r.err;
  EXPECT_NE(r.err.find("mrr: error: " + (fs::path(shaders) / "ssao.frag").string() + ":16: "), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;

  // in an include: the include's own line
  writeText(file, text);
  const fs::path common = fs::path(shaders) / "common.glsl";
  writeText(common, "// line 1\n// line 2\nthis is not glsl\n");
  r = mrr(compareArgs("ssao", {"--shaders", shaders}), dir);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("mrr: error: " + common.string() + ":3: "), std::string::npos) << r.err;
}

TEST(ShadersDir, StrayFileGetsAWarningListingTheNames) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir, {"ssao.frag"});
  writeText(fs::path(shaders) / "ssao2.frag", "#version 330 core\nvoid main() {}\n");
  const Ran r = mrr({"render", "--scene", "builtin:demo", "--path", "gpu", "--size", "64x36", "--samples", "4", "-q",
                     "--out", (fs::path(dir) / "o.exr").string(), "--shaders", shaders},
                    dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("mrr: warning: " + (fs::path(shaders) / "ssao2.frag").string() + " is no shader of mrr"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("mrr's shaders: albedo.glsl, bilateral.frag, bilateral.glsl, blend.frag"), std::string::npos) << r.err;
}

TEST(ShadersDir, AnUnusedUniformIsSkippedAndAMissingOutputIsNamed) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir, {"ssao.frag"});
  const fs::path file = fs::path(shaders) / "ssao.frag";
  const std::string text = test::readFile(file.string());
  // the bias fixed in the shader: the host's `bias` is no longer used. A uniform the program does
  // not use is skipped (only the stage's outputs are insisted on), so the frame renders, and
  // compare catches the different AO at the stage the shader makes.
  writeText(file, edited(text, "uniform float bias;", "const float bias = 0.0;"));
  Ran r = mrr(compareArgs("ssao", {"--shaders", shaders}), dir);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.err.find("lacks the uniform bias"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("FAIL: first failing stage raw.L0 (ssao.frag)"), std::string::npos) << r.out;
  // the output renamed and moved
  writeText(file, edited(text, "layout(location = 0) out vec4 ao;", "layout(location = 1) out vec4 occl;"));
  std::string t = test::readFile(file.string());
  for (size_t at = t.find("ao = "); at != std::string::npos; at = t.find("ao = ", at)) t.replace(at, 5, "occl = ");
  writeText(file, t);
  r = mrr(compareArgs("ssao", {"--shaders", shaders}), dir);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find(file.string() + ": stage ssao: lacks the output ao at location 0"), std::string::npos) << r.err;
}

// ---- compare --against: another renderer's stages ---------------------------------------

const std::vector<std::string> kFrame = {"--scene", "builtin:demo", "--effect", "ssao", "--size", "160x90", "--samples",
                                         "8", "-q"};

// The oracle's own stages EXR of kFrame (compare turns never-slower off; so does this render).
std::string oracleStages(const std::string& dir) {
  const std::string file = (fs::path(dir) / "oracle-stages.exr").string();
  const Ran r = mrr(with(with({"render", "--never-slower", "off", "--stages", file}, kFrame), {}), dir);
  EXPECT_EQ(r.status, 0) << r.err;
  return file;
}

TEST(CompareAgainst, TheOraclesOwnStagesPass) {
  const std::string dir = test::scratchDir();
  const std::string stages = oracleStages(dir);
  const Ran r = mrr(with(with({"compare", "--against", stages}, kFrame), {}), dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("oracle (cpu_ref) vs " + stages), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("not checked"), std::string::npos) << r.out;  // every stage is there
  EXPECT_NE(r.out.find("\nraw.L1 "), std::string::npos) << r.out;
  EXPECT_EQ(lastLine(r.out), "PASS: every stage within tolerance") << r.out;
}

// Tiles with a gaze and motion: the tile rates are written and read back, and the padded full-res
// parts (eccentricity, motion, level limit; W×H in the file) go back into their padded grids: the
// oracle's own stages pass, each on its own inputs.
TEST(CompareAgainst, TheOraclesOwnTilesAndFoveationStagesPass) {
  const std::string dir = test::scratchDir();
  const std::vector<std::string> frame =
      with(kFrame, {"--method", "tiles", "--gaze", "40,30", "--ppd", "8", "--pan", "0.3"});
  const std::string stages = (fs::path(dir) / "tiles-stages.exr").string();
  Ran r = mrr(with({"render", "--never-slower", "off", "--stages", stages}, frame), dir);
  ASSERT_EQ(r.status, 0) << r.err;
  r = mrr(with({"compare", "--against", stages}, frame), dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_EQ(r.out.find("not checked"), std::string::npos) << r.out;
  for (const char* row : {"\ntilerates ", "\neccentricity ", "\nlevellimit "})
    EXPECT_NE(r.out.find(row), std::string::npos) << row << r.out;
  EXPECT_NE(r.out.find("levellimit.same_input"), std::string::npos) << r.out;
  EXPECT_EQ(lastLine(r.out), "PASS: every stage within tolerance") << r.out;
}

// One part altered the way a bug would: the effect of level 1 a few per cent darker. End to
// end it is within the SSAO rule; on its own inputs it is not: FAIL at raw.L1.
TEST(CompareAgainst, AnAlteredPartFailsAtItsStage) {
  const std::string dir = test::scratchDir();
  std::vector<ExrPart> parts = readParts(oracleStages(dir));
  bool found = false;
  for (ExrPart& p : parts)
    if (p.name == "raw.L1") {
      for (float& v : p.image.data) v *= 0.97f;
      found = true;
    }
  ASSERT_TRUE(found);
  const std::string altered = (fs::path(dir) / "altered.exr").string();
  writeMultiPartExr(altered, parts, 160, 90);
  const Ran r = mrr(with({"compare", "--against", altered}, kFrame), dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out), "FAIL: first failing stage raw.L1 (ssao.frag)") << r.out;
}

// A folder with final.exr alone (what `render --out` writes): judged end to end; the rest is
// listed as not checked.
TEST(CompareAgainst, FinalAloneInAFolder) {
  const std::string dir = test::scratchDir();
  const fs::path folder = fs::path(dir) / "foreign";
  fs::create_directories(folder);
  Ran r = mrr(with({"render", "--never-slower", "off", "--out", (folder / "final.exr").string()}, kFrame), dir);
  ASSERT_EQ(r.status, 0) << r.err;
  r = mrr(with({"compare", "--against", folder.string()}, kFrame), dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("not checked (absent from " + folder.string() + "): gbuffer.L0, "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nfinal "), std::string::npos) << r.out;
  EXPECT_EQ(lastLine(r.out), "PASS: every stage within tolerance") << r.out;
  // the same final, darker by 3%: fails at final
  std::vector<ExrPart> parts = readParts((folder / "final.exr").string());
  for (float& v : parts.front().image.data) v *= 0.97f;
  writeImage((folder / "final.exr").string(), parts.front().image, parts.front().channelNames);
  r = mrr(with({"compare", "--against", folder.string()}, kFrame), dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out), "FAIL: first failing stage final (blend.frag)") << r.out;
}

TEST(CompareAgainst, WrongSizeOrMissingChannelIsNamed) {
  const std::string dir = test::scratchDir();
  const fs::path folder = fs::path(dir) / "foreign";
  fs::create_directories(folder);
  writeImage((folder / "final.exr").string(), ImageF(80, 45, 1, 0.5f), {"Y"});
  Ran r = mrr(with({"compare", "--against", folder.string()}, kFrame), dir);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("mrr: error: --against " + folder.string() + ": part final is 80x45, expected 160x90"),
            std::string::npos)
      << r.err;
  fs::remove(folder / "final.exr");
  writeImage((folder / "edges.exr").string(), ImageF(160, 90, 3, 0.0f), {"normal", "depth", "background"});
  r = mrr(with({"compare", "--against", folder.string()}, kFrame), dir);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("part edges lacks channel E (it has depth background normal)"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

// The port's stages, as another renderer would hand them over: they pass.
TEST(CompareAgainst, ThePortsStagesPass) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string stages = (fs::path(dir) / "port-stages.exr").string();
  Ran r = mrr(with({"render", "--path", "gpu", "--never-slower", "off", "--stages", stages}, kFrame), dir);
  ASSERT_EQ(r.status, 0) << r.err;
  r = mrr(with({"compare", "--against", stages}, kFrame), dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out).rfind("PASS", 0), 0u) << r.out;
}

// probe --path both with --against and with --shaders: each value with its tolerance.
TEST(ProbeBoth, AgainstAndShadersShowTolerances) {
  const std::string dir = test::scratchDir();
  const std::string stages = oracleStages(dir);
  Ran r = mrr(with({"probe", "--path", "both", "--pixel", "80,45", "--against", stages}, kFrame), dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("how they are compared"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(final)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("the paths agree at every stage"), std::string::npos) << r.out;
  REQUIRE_GL(dir);
  const std::string shaders = exportShaders(dir, {"ssao.frag"});
  r = mrr(loud(with({"probe", "--path", "both", "--pixel", "80,45", "--shaders", shaders}, kFrame)), dir);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("shaders from " + shaders + ": ssao.frag (built in: the rest)"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("(ssao)"), std::string::npos) << r.out;
}

// ---- examples/ (docs/validate-your-own.md): each one's verdict and the stage it names ----

std::string example(const std::string& name) { return (fs::path(MRR_SOURCE_DIR) / "examples" / name).string(); }

TEST(Examples, RewrittenSsaoPasses) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const Ran r = mrr(loud(compareArgs("ssao", {"--shaders", example("ssao-rewritten")})), dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.err.find("ssao-rewritten: ssao.frag (built in: the rest)"), std::string::npos) << r.err;
  EXPECT_EQ(lastLine(r.out), "PASS: every stage within tolerance") << r.out;
}

TEST(Examples, PaperBlendIndexFailsAtTheComposite) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const Ran r = mrr(compareArgs("ssao", {"--shaders", example("blend-paper-index")}), dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out).rfind("FAIL: first failing stage composite.L", 0), 0u) << r.out;
}

TEST(Examples, ForeignRendererScriptIsNamedByCompare) {
  const std::string dir = test::scratchDir();
  if (std::system("/usr/bin/python3 -c 'import OpenImageIO, numpy' 2>/dev/null") != 0)
    GTEST_SKIP() << "no python3-openimageio/python3-numpy for /usr/bin/python3 (scripts/install-deps.sh installs them)";
  const std::string stages = oracleStages(dir);
  // The verdict names the stage and the port's shader that computes it (the stage list's).
  for (const auto& [bug, stage] :
       {std::pair<std::string, std::string>{"edges", "edges.depth (edges.frag)"}, {"raw", "raw.L0 (ssao.frag)"}}) {
    const std::string altered = (fs::path(dir) / (bug + ".exr")).string();
    const std::string cmd = "/usr/bin/python3 " + quote(example("foreign_renderer.py")) + " " + quote(stages) + " " +
                            quote(altered) + " --bug " + bug + " --samples 8 >/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
    const Ran r = mrr(with({"compare", "--against", altered}, kFrame), dir);
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_EQ(lastLine(r.out), "FAIL: first failing stage " + stage) << bug << "\n" << r.out;
  }
}

}  // namespace
}  // namespace mrr
