#pragma once
// mrr's subcommands, one pair each: add*Command registers the subcommand and its options on the
// top-level app, run* carries it out once the command line is parsed (exit 0, 1 for a verdict
// that failed, MrrError for bad input: exit 2). app/main.cpp only parses and dispatches.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <mutex>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "common/frame.h"
#include "compare/bench/bench.h"
#include "explore/server.h"
#include "frontend/frame_options.h"
#include "scenes/catalog.h"

namespace mrr {

// ---- Shared by the commands (app/command_support.cpp) -------------------------------------------
// Checks that `path` ends in one of `extensions` (any case) and can be written, before any work.
void checkOutput(const std::string& path, const std::string& option, const std::vector<std::string>& extensions);
// Two options naming one file would silently overwrite each other.
void requireDistinct(const std::vector<std::pair<std::string, std::string>>& outputs);
// "[mrr] WHAT: stage" lines on stderr, or nothing when quiet.
ProgressFn progressPrinter(bool quiet, const std::string& what);
int threadCount(int requested);  // 0: every core TBB may use
// `--report DIR`: the folder is made, parents too, as `mkdir -p` would, and checked writable.
void makeReportDir(const std::string& dir, const std::string& option = "--report");
// A frame as command-line options, quoted for a POSIX shell where needed.
std::string frameCommandLine(const nlohmann::json& frame);

// ---- render and probe (app/render_command.cpp) ----------------------------------------------------
struct RenderCommand {
  CLI::App* command = nullptr;
  FrameOptions frame;
  std::string out, shaded, stages, report, frameOut;
  bool reference = false;
};
void addRenderCommand(CLI::App& app, RenderCommand& c);
int runRenderCommand(RenderCommand& c);

struct ProbeCommand {
  CLI::App* command = nullptr;
  FrameOptions frame;
  std::string pixel;
  bool json = false;
  std::string against;  // --against FILE (with --path both)
  bool noiseAware = false;  // --noise-aware (with --path both): the stochastic stages' means and intervals
};
void addProbeCommand(CLI::App& app, ProbeCommand& c);
int runProbeCommand(ProbeCommand& c);

// ---- compare (app/compare_command.cpp) --------------------------------------------------------------
struct CompareCommand {
  CLI::App* command = nullptr;
  FrameOptions frame;
  std::string reportDir;
  std::string against;  // --against FILE: another renderer's stages instead of the port
  bool noiseAware = false;  // --noise-aware: the stochastic stages judged statistically (compare/parity/noise.h)
};
void addCompareCommand(CLI::App& app, CompareCommand& c);
int runCompareCommand(CompareCommand& c);

// compare's work on one frame, shared with check. prepareCompare checks everything that can be
// checked before any rendering (the path, the --against file, threads, the report folder,
// memory; MrrError) and gives the settings of each effect compared. compareFrame renders and
// judges them; `out` gets the tables compare prints (nothing when null). `portLock`, when given,
// is held while the port renders, with a renderer (and GL context) of its own made and closed
// under it: check --jobs runs frames side by side, the port one at a time.
struct CompareOutcome {
  bool pass = true;
  std::string effect;        // the first failing frame's effect
  std::string firstFailing;  // its first failing stage ("ssm:edges" when several effects are compared); "" on PASS
  std::string figures;       // the check that failed it: "ssao.same_input max|d| 0.03  rms 0.0269  over 85.4% of 12036"
  std::string tables;        // what compare prints on stdout
  std::string subject;       // the port's GL renderer, or the --against file
  std::string scene;         // the scene as resolved
};
std::vector<Settings> prepareCompare(CompareCommand& c);
CompareOutcome compareFrame(const CompareCommand& c, const std::vector<Settings>& settings, std::ostream* out,
                            std::mutex* portLock = nullptr);

// ---- check (app/check_command.cpp): a folder of frame files, one compare each ----------------
struct CheckCommand {
  CLI::App* command = nullptr;
  std::string dir;                  // the suite: a folder of frame files
  std::string against;              // --against ADIR: ADIR/CASE.exr or ADIR/CASE/ per case
  std::string junit, json, reportDir, shard;
  std::vector<std::string> merge;   // --merge R1.json R2.json ...: shards' results joined
  std::string shaders;              // --shaders SDIR (main.cpp loads them; named in the summary)
  int jobs = 1, threads = 0, glDevice = -1;
  bool quiet = false;
  bool noiseAware = false;          // --noise-aware: each case's stochastic stages judged statistically (compare/parity/noise.h)
};
void addCheckCommand(CLI::App& app, CheckCommand& c);
int runCheckCommand(CheckCommand& c);

// ---- bench (app/bench_command.cpp) --------------------------------------------------------------------
struct BenchCommand {
  CLI::App* command = nullptr;
  BenchOptions options;
  std::vector<std::string> sizes, resolutions, paths = {"cpu"};
  std::string sweepSize, stabilitySize, stressSize, calibrateOut, ruleSweepOut, ruleReplayIn, ruleCostModelFile;
  std::string foveaSize, foveaMotionSize;  // the foveation group's (compare/bench/bench_fovea.h)
  bool quick = false, noSweeps = false, noStress = false, noFovea = false;
  PathOptions path;
};
void addBenchCommand(CLI::App& app, BenchCommand& c);
int runBenchCommand(BenchCommand& c);

// ---- info and explore (app/info.cpp, app/main.cpp) ------------------------------------------------------
struct InfoCommand {
  CLI::App* command = nullptr;
  SceneRequest request;
  std::string size = "1280x720", blendMaterials = "opaque";
  std::optional<float> fov;
  bool json = false, flipUp = false, noFlipUp = false;
};
void addInfoCommand(CLI::App& app, InfoCommand& c);
int runInfoCommand(InfoCommand& c);

}  // namespace mrr
