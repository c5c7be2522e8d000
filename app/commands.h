#pragma once
// mrr's subcommands, one pair each: add*Command registers the subcommand and its options on the
// top-level app, run* carries it out once the command line is parsed (exit 0, 1 for a verdict
// that failed, MrrError for bad input: exit 2). app/main.cpp only parses and dispatches.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/frame.h"
#include "compare/bench.h"
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
};
void addProbeCommand(CLI::App& app, ProbeCommand& c);
int runProbeCommand(ProbeCommand& c);

// ---- compare (app/compare_command.cpp) --------------------------------------------------------------
struct CompareCommand {
  CLI::App* command = nullptr;
  FrameOptions frame;
  std::string reportDir;
  std::string against;  // --against FILE: another renderer's stages instead of the port
};
void addCompareCommand(CLI::App& app, CompareCommand& c);
int runCompareCommand(CompareCommand& c);

// ---- bench (app/bench_command.cpp) --------------------------------------------------------------------
struct BenchCommand {
  CLI::App* command = nullptr;
  BenchOptions options;
  std::vector<std::string> sizes, resolutions, paths = {"cpu"};
  std::string sweepSize, stabilitySize, stressSize, calibrateOut, ruleSweepOut, ruleReplayIn, ruleCostModelFile;
  bool quick = false, noSweeps = false, noStress = false;
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
