// `mrr check DIR`: a suite of frame files, run through the real binary. The frames are
// tiny (64x36, few samples) so that a suite takes seconds. CheckDocs runs the commands of
// docs/validate-your-own.md's section 5 as they stand there and checks each exit status and line.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/image_io.h"
#include "tests/cli/run_mrr.h"
#include "tests/test_support.h"

namespace mrr {
namespace {
namespace fs = std::filesystem;

using cli::lastLine;
using cli::quote;
using cli::Ran;
// Runs in DIR: the suite's folders are named relative to it.
Ran mrrIn(const std::vector<std::string>& args, const std::string& dir) { return cli::mrr(args, dir, "", true); }

// The four good frames of the docs' suite, in DIR/frames.
std::string makeFrames(const std::string& dir) {
  const fs::path frames = fs::path(dir) / "frames";
  fs::create_directories(frames);
  for (const auto& [name, scene, effect, samples] :
       std::vector<std::tuple<std::string, std::string, std::string, std::string>>{{"demo-ssao", "builtin:demo", "ssao", "8"},
                                                                                  {"boxes-ssao", "builtin:boxes", "ssao", "8"},
                                                                                  {"demo-ssm", "builtin:demo", "ssm", "9"},
                                                                                  {"demo-ssgi", "builtin:demo", "ssgi", "8"}}) {
    const Ran r = mrrIn({"render", "--scene", scene, "--effect", effect, "--size", "64x36", "--samples", samples,
                         "--never-slower", "off", "-q", "--frame-out", (frames / (name + ".json")).string()},
                        dir);
    EXPECT_EQ(r.status, 0) << r.err;
  }
  return frames.string();
}

// The summary's rows: case -> the row's words, the time left out.
std::map<std::string, std::string> rows(const std::string& summary) {
  std::map<std::string, std::string> out;
  std::istringstream lines(summary);
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string x; words >> x;) w.push_back(x);
    if (w.size() == 7 && w.back() == "s") out[w[0]] = w[1] + " " + w[2] + " " + w[3] + " " + w[4];
  }
  return out;
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Check, FourGoodFramesPassWithJunit) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string frames = makeFrames(dir);
  const Ran r = mrrIn({"check", frames, "--junit", "junit.xml"}, dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out), "PASS: all 4 cases") << r.out;
  EXPECT_EQ(rows(r.out), (std::map<std::string, std::string>{{"boxes-ssao", "ssao mrr PASS -"},
                                                             {"demo-ssao", "ssao mrr PASS -"},
                                                             {"demo-ssgi", "ssgi mrr PASS -"},
                                                             {"demo-ssm", "ssm mrr PASS -"}}))
      << r.out;
  for (int i = 1; i <= 4; ++i) EXPECT_NE(r.err.find("[mrr] check " + std::to_string(i) + "/4 "), std::string::npos) << r.err;
  const std::string junit = test::readFile((fs::path(dir) / "junit.xml").string());
  EXPECT_EQ(count(junit, "<testcase "), 4u) << junit;
  EXPECT_NE(junit.find("tests=\"4\" failures=\"0\" errors=\"0\""), std::string::npos) << junit;
  EXPECT_EQ(junit.find("<failure"), std::string::npos) << junit;
  EXPECT_NE(junit.find("classname=\"mrr.check.ssm\" name=\"demo-ssm\""), std::string::npos) << junit;
}

// The SSAO shader 3% too dark: the SSAO cases fail at the stage it computes, the others pass.
TEST(Check, DarkerSsaoShaderFailsTheSsaoCases) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string frames = makeFrames(dir);
  const std::string shaders = (fs::path(dir) / "darker").string();
  ASSERT_EQ(mrrIn({"shaders", "export", shaders}, dir).status, 0);
  const fs::path file = fs::path(shaders) / "ssao.frag";
  std::string text = test::readFile(file.string());
  const std::string find = "ao = vec4(1.0 - occlusion / float(samples), 0.0, 0.0, 1.0);";
  ASSERT_NE(text.find(find), std::string::npos) << "the shader no longer holds: " << find;
  text.replace(text.find(find), find.size(), "ao = vec4((1.0 - occlusion / float(samples)) * 0.97, 0.0, 0.0, 1.0);");
  std::ofstream(file, std::ios::binary) << text;
  const Ran r = mrrIn({"check", frames, "--shaders", shaders, "--junit", "junit.xml", "--jobs", "2"}, dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out), "FAIL: 2 of 4 cases failed") << r.out;
  const std::map<std::string, std::string> got = rows(r.out);
  EXPECT_EQ(got.at("demo-ssao"), "ssao mrr FAIL raw.L0") << r.out;
  EXPECT_EQ(got.at("boxes-ssao"), "ssao mrr FAIL raw.L0") << r.out;
  EXPECT_EQ(got.at("demo-ssm"), "ssm mrr PASS -") << r.out;
  EXPECT_EQ(got.at("demo-ssgi"), "ssgi mrr PASS -") << r.out;
  const std::string junit = test::readFile((fs::path(dir) / "junit.xml").string());
  EXPECT_NE(junit.find("tests=\"4\" failures=\"2\" errors=\"0\""), std::string::npos) << junit;
  EXPECT_EQ(count(junit, "<failure message=\"first failing stage raw.L0: ssao.same_input max|d| "), 2u) << junit;
  EXPECT_NE(junit.find("FAIL: first failing stage raw.L0 (ssao.frag)\n</failure>"), std::string::npos) << junit;  // compare's table
}

// The shards partition the cases; their merged results are the whole suite's summary.
TEST(Check, ShardsPartitionAndMergeToTheWholeSuite) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string frames = makeFrames(dir);
  std::ofstream(fs::path(frames) / "broken.json") << "{\"scene\": \"builtin:demo\", \"size\": \"64x36\", \"bogus\": 1}";
  const Ran whole = mrrIn({"check", frames, "-q"}, dir);
  EXPECT_EQ(whole.status, 2) << whole.out << whole.err;
  std::set<std::string> seen;
  for (const char* shard : {"1/2", "2/2"}) {
    const std::string json = std::string("shard-") + shard[0] + ".json";
    const Ran r = mrrIn({"check", frames, "--shard", shard, "--json", json, "-q"}, dir);
    EXPECT_TRUE(r.status == 0 || r.status == 2) << r.out << r.err;
    for (const auto& [name, row] : rows(r.out)) EXPECT_TRUE(seen.insert(name).second) << name << " in two shards";
    const nlohmann::json results = nlohmann::json::parse(test::readFile((fs::path(dir) / json).string()));
    EXPECT_EQ(results["cases_in_suite"], 5);
    EXPECT_EQ(results["cases"].size(), rows(r.out).size());
  }
  EXPECT_EQ(seen, (std::set<std::string>{"boxes-ssao", "broken", "demo-ssao", "demo-ssgi", "demo-ssm"}));
  const Ran merged = mrrIn({"check", "--merge", "shard-1.json", "shard-2.json", "--junit", "junit.xml"}, dir);
  EXPECT_EQ(merged.status, whole.status) << merged.out << merged.err;
  const std::regex time(" +[0-9]+\\.[0-9]+ s\n");
  EXPECT_EQ(std::regex_replace(merged.out, time, "\n"), std::regex_replace(whole.out, time, "\n"));
  EXPECT_EQ(count(test::readFile((fs::path(dir) / "junit.xml").string()), "<testcase "), 5u);
  // A shard missing, or given twice: refused, one line.
  Ran r = mrrIn({"check", "--merge", "shard-1.json"}, dir);
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "mrr: error: --merge: shard 2/2 missing (give every shard's --json results)\n");
  r = mrrIn({"check", "--merge", "shard-1.json", "shard-1.json", "shard-2.json"}, dir);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("are both shard 1/2"), std::string::npos) << r.err;
}

// A broken frame file is one ERROR case with its one-line message; the others still run.
TEST(Check, BrokenFrameIsOneErrorCase) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string frames = makeFrames(dir);
  std::ofstream(fs::path(frames) / "typo.json") << R"({"scene": "builtin:demo", "size": "64x36", "samples": "eight"})";
  std::ofstream(fs::path(frames) / "garbage.json") << "not json";
  const Ran r = mrrIn({"check", frames, "--junit", "junit.xml", "--jobs", "3", "-q"}, dir);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  EXPECT_EQ(lastLine(r.out), "ERROR: 2 of 6 cases could not run; 0 failed") << r.out;
  const std::map<std::string, std::string> got = rows(r.out);
  EXPECT_EQ(got.at("typo"), "ssao mrr ERROR -");
  EXPECT_EQ(got.at("garbage"), "- - ERROR -");
  for (const char* good : {"demo-ssao", "boxes-ssao", "demo-ssm", "demo-ssgi"}) EXPECT_EQ(got.at(good).substr(got.at(good).size() - 6), "PASS -") << good;
  EXPECT_NE(r.out.find("\ntypo: ERROR: " + (fs::path(frames) / "typo.json").string() +
                       ": \"samples\": expected a whole number\n"),
            std::string::npos)
      << r.out;
  const std::string junit = test::readFile((fs::path(dir) / "junit.xml").string());
  EXPECT_NE(junit.find("tests=\"6\" failures=\"0\" errors=\"2\""), std::string::npos) << junit;
  EXPECT_EQ(count(junit, "<error message="), 2u) << junit;
}

// --against ADIR: CASE.exr or CASE/ per case; a case without stages is an ERROR.
TEST(Check, AgainstAFolderOfStages) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const std::string frames = makeFrames(dir);
  const fs::path stages = fs::path(dir) / "stages";
  fs::create_directories(stages / "demo-ssm");
  for (const char* c : {"demo-ssao", "boxes-ssao"})
    ASSERT_EQ(mrrIn({"render", "--frame", (fs::path(frames) / (std::string(c) + ".json")).string(), "-q", "--stages",
                     (stages / (std::string(c) + ".exr")).string()},
                    dir)
                  .status,
              0);
  ASSERT_EQ(mrrIn({"render", "--frame", (fs::path(frames) / "demo-ssm.json").string(), "-q", "--out",
                   (stages / "demo-ssm" / "final.exr").string()},
                  dir)
                .status,
            0);
  const Ran r = mrrIn({"check", frames, "--against", stages.string(), "-q"}, dir);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  const std::map<std::string, std::string> got = rows(r.out);
  EXPECT_EQ(got.at("demo-ssao"), "ssao mrr PASS -") << r.out;
  EXPECT_EQ(got.at("boxes-ssao"), "ssao mrr PASS -") << r.out;
  EXPECT_EQ(got.at("demo-ssm"), "ssm mrr PASS -") << r.out;
  EXPECT_EQ(got.at("demo-ssgi"), "ssgi mrr ERROR -") << r.out;
  EXPECT_NE(r.out.find("demo-ssgi: ERROR: --against " + stages.string() + ": no stages for case demo-ssgi"), std::string::npos)
      << r.out;
}

// check --noise-aware: a renderer with its own noise (here the oracle's stages drawn
// with --seed 7) fails every SSAO case exactly and passes them noise-aware; the same 3% too dark
// fails noise-aware at raw.L0, and SSM (no stochastic stage) is judged as without the flag.
TEST(Check, NoiseAwareJudgesOwnNoiseStatistically) {
  const std::string dir = test::scratchDir();
  const fs::path frames = fs::path(dir) / "frames", stages = fs::path(dir) / "stages", dark = fs::path(dir) / "dark";
  for (const fs::path& p : {frames, stages, dark}) fs::create_directories(p);
  const std::vector<std::string> common = {"--size", "96x54", "--never-slower", "off", "-q"};
  for (const auto& [name, scene, effect, samples] : std::vector<std::tuple<std::string, std::string, std::string, std::string>>{
           {"demo-ssao", "builtin:demo", "ssao", "8"}, {"boxes-ssao", "builtin:boxes", "ssao", "8"},
           {"demo-ssm", "builtin:demo", "ssm", "9"}}) {
    std::vector<std::string> frame = {"render", "--scene", scene, "--effect", effect, "--samples", samples};
    frame.insert(frame.end(), common.begin(), common.end());
    std::vector<std::string> file = frame;
    file.insert(file.end(), {"--frame-out", (frames / (name + ".json")).string()});
    ASSERT_EQ(mrrIn(file, dir).status, 0);
    std::vector<std::string> theirs = frame;
    theirs.insert(theirs.end(), {"--seed", "7", "--stages", (stages / (name + ".exr")).string()});
    ASSERT_EQ(mrrIn(theirs, dir).status, 0);
    std::vector<ExrPart> parts = readParts((stages / (name + ".exr")).string());
    for (ExrPart& p : parts)
      if (p.name.rfind("raw.L", 0) == 0 && effect == "ssao")
        for (float& v : p.image.data) v *= 0.97f;
    writeMultiPartExr((dark / (name + ".exr")).string(), parts, 96, 54);
  }
  Ran r = mrrIn({"check", frames.string(), "--against", stages.string(), "-q"}, dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  std::map<std::string, std::string> got = rows(r.out);
  EXPECT_EQ(got["demo-ssao"], "ssao mrr FAIL raw.L0") << r.out;
  EXPECT_EQ(got["boxes-ssao"], "ssao mrr FAIL raw.L0") << r.out;
  EXPECT_EQ(got["demo-ssm"], "ssm mrr PASS -") << r.out;

  const std::string results = (fs::path(dir) / "noise.json").string();
  r = mrrIn({"check", frames.string(), "--against", stages.string(), "--noise-aware", "-q", "--json", results}, dir);
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  got = rows(r.out);
  EXPECT_EQ(got["demo-ssao"], "ssao mrr PASS -") << r.out;
  EXPECT_EQ(got["boxes-ssao"], "ssao mrr PASS -") << r.out;
  EXPECT_EQ(got["demo-ssm"], "ssm mrr PASS -") << r.out;
  EXPECT_NE(test::readFile(results).find("noise-aware (the stochastic stages against the oracle's 16 seeds)"),
            std::string::npos);

  r = mrrIn({"check", frames.string(), "--against", dark.string(), "--noise-aware", "-q"}, dir);
  EXPECT_EQ(r.status, 1) << r.out << r.err;
  got = rows(r.out);
  EXPECT_EQ(got["demo-ssao"], "ssao mrr FAIL raw.L0") << r.out;
  EXPECT_EQ(got["demo-ssm"], "ssm mrr PASS -") << r.out;
  const size_t line = r.out.find("demo-ssao: FAIL: first failing stage raw.L0: ");
  ASSERT_NE(line, std::string::npos) << r.out;
  EXPECT_NE(r.out.substr(line, r.out.find('\n', line) - line).find("bias -"), std::string::npos) << r.out;
}

// --report: the index links each case's compare page, and a FAIL's stage.
TEST(Check, ReportIndexLinksEveryCasePage) {
  const std::string dir = test::scratchDir();
  if (std::system("/usr/bin/python3 -c 'import matplotlib, jinja2' 2>/dev/null") != 0)
    GTEST_SKIP() << "no matplotlib/Jinja2 for /usr/bin/python3 (scripts/install-deps.sh installs them)";
  REQUIRE_GL(dir);
  const std::string frames = makeFrames(dir);
  std::ofstream(fs::path(frames) / "garbage.json") << "not json";
  const Ran r = mrrIn({"check", frames, "--report", "report", "-q"}, dir);
  EXPECT_EQ(r.status, 2) << r.out << r.err;
  const std::string index = test::readFile((fs::path(dir) / "report" / "index.html").string());
  for (const char* c : {"demo-ssao", "boxes-ssao", "demo-ssm", "demo-ssgi"}) {
    EXPECT_NE(index.find("href=\"" + std::string(c) + "/index.html\""), std::string::npos) << c;
    EXPECT_TRUE(fs::exists(fs::path(dir) / "report" / c / "index.html")) << c;
  }
  EXPECT_NE(index.find("data-case=\"garbage\""), std::string::npos);
  EXPECT_FALSE(fs::exists(fs::path(dir) / "report" / "garbage"));  // no page, no folder
}

TEST(Check, UsageErrorsAreOneLine) {
  const std::string dir = test::scratchDir();
  fs::create_directories(fs::path(dir) / "frames");
  fs::create_directories(fs::path(dir) / "empty");
  std::ofstream(fs::path(dir) / "frames" / "a.json") << "{}";
  for (const auto& [args, message] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"check"}, "check: a folder of frame files is required (mrr check DIR), or --merge R1.json R2.json ..."},
           {{"check", "missing"}, "check missing: no such folder (expected a folder of frame files, *.json)"},
           {{"check", "empty"}, "check empty: holds no frame file (*.json, as `mrr render --frame-out` writes)"},
           {{"check", "frames", "--shard", "3/2"}, "--shard 3/2: expected I/N with 1 <= I <= N, e.g. 1/4"},
           {{"check", "frames", "--junit", "j.txt"}, "--junit j.txt: expected a .xml file"},
           {{"check", "frames", "--jobs", "0"}, "--jobs 0: must be in [1, 256]"},
           {{"check", "frames", "--json", "frames/r.json"},
            "--json frames/r.json: inside the suite's folder frames, it would be read as a case; write it elsewhere"},
           {{"check", "frames", "--merge", "r.json"}, "check: a folder or --merge, not both (--merge joins results already run)"},
           {{"check", "--merge", "r.json"}, "--merge r.json: cannot read the file"},
           {{"check", "--merge", "r.json", "--noise-aware"},
            "check --merge: --against, --shard, --shaders and --noise-aware are for running a suite, not for merging results"},
       }) {
    const Ran r = mrrIn(args, dir);
    EXPECT_EQ(r.status, 2) << args.back();
    EXPECT_EQ(r.err, "mrr: error: " + message + "\n") << args.back();
    EXPECT_EQ(r.out, "") << args.back();
  }
}

// ---- docs/validate-your-own.md, section 5: its commands, run as they stand there ----

// A line as compared: times ("0.12 s") masked, the figures after max|d| left out (they are the
// GL driver's), runs of spaces as one.
std::string normalised(const std::string& line) {
  std::string s = std::regex_replace(line, std::regex("[0-9]+\\.[0-9]+ s\\b"), "T s");
  if (const size_t at = s.find("max|d|"); at != std::string::npos) s = s.substr(0, at);
  s = std::regex_replace(s, std::regex(" +"), " ");
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

struct DocCommand {
  std::string command;
  std::vector<std::string> output;  // the lines shown (less "exit N")
  int status = 0;
};

std::vector<DocCommand> docCommands() {
  std::ifstream in(fs::path(MRR_SOURCE_DIR) / "docs" / "validate-your-own.md");
  std::vector<DocCommand> out;
  bool inSection = false, inBlock = false, runs = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## ", 0) == 0) inSection = line.rfind("## 5.", 0) == 0;
    if (!inSection) continue;
    if (line.rfind("```", 0) == 0) {
      runs = !inBlock && line == "```";  // ```yaml: the CI example, not run
      inBlock = !inBlock;
      continue;
    }
    if (!inBlock || !runs) continue;
    if (line.rfind("$ ", 0) == 0) out.push_back({line.substr(2), {}, 0});
    else if (!out.empty() && line.rfind("exit ", 0) == 0) out.back().status = std::stoi(line.substr(5));
    else if (!out.empty() && line != "…") out.back().output.push_back(line);
  }
  return out;
}

TEST(CheckDocs, CommandsGiveTheOutputShown) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  fs::create_directories(fs::path(dir) / "bin");
  fs::create_symlink(MRR_BINARY, fs::path(dir) / "bin" / "mrr");
  const std::vector<DocCommand> commands = docCommands();
  ASSERT_GE(commands.size(), 15u) << "docs/validate-your-own.md lost its section 5";
  for (const DocCommand& c : commands) {
    const std::string script = (fs::path(dir) / "command.sh").string();
    std::ofstream(script) << c.command << "\n";
    const std::string run = "cd " + quote(dir) + " && PATH=" + quote((fs::path(dir) / "bin").string()) +
                            ":\"$PATH\" bash command.sh >out.txt 2>&1";
    const int raw = std::system(run.c_str());
    const int status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    const std::string got = test::readFile((fs::path(dir) / "out.txt").string());
    EXPECT_EQ(status, c.status) << c.command << "\n" << got;
    std::set<std::string> lines;
    std::istringstream text(got);
    for (std::string l; std::getline(text, l);) lines.insert(normalised(l));
    for (const std::string& want : c.output) EXPECT_TRUE(lines.count(normalised(want))) << c.command << "\nshown: " << want << "\ngot:\n" << got;
  }
}

}  // namespace
}  // namespace mrr
