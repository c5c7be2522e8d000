#pragma once
// Bring your own: the command line of `--shaders DIR`, `mrr shaders export|contract`
// and `compare --against FILE`, kept apart from main.cpp so the subcommands share one helper.
#include <CLI/CLI.hpp>

#include <string>

namespace mrr {

// `--shaders DIR` on a subcommand, bound to `dir`.
void addShadersOption(CLI::App& command, std::string& dir);

// Loads DIR's shaders in place of the built-ins (gpu::loadShaderDirectory) and says once on
// stderr which files came from DIR; a file that is no shader of mrr gets a warning listing
// those that are. A missing DIR: MrrError. Nothing when `dir` is empty. `quiet` (-q) drops the
// line saying which files came from DIR; warnings still print.
void useShaderDirectory(const std::string& dir, bool quiet = false);

struct ForeignStages;

// `--against FILE` on compare and probe, bound to `file`.
void addAgainstOption(CLI::App& command, std::string& file);
// Before anything renders: FILE exists, and is a stages file (a part, or a folder's PART.exr,
// named like a stage); one effect at a time. MrrError otherwise.
void checkForeignStagesFile(const std::string& file, const std::string& effect);
// "not checked (absent from FILE): a, b, …\n", or "" when the file holds every stage.
std::string formatNotChecked(const ForeignStages& foreign);

// `mrr shaders export DIR` and `mrr shaders contract`.
struct ShadersCommand {
  CLI::App* command = nullptr;
  CLI::App* exportCommand = nullptr;
  CLI::App* contractCommand = nullptr;
  std::string exportDir;
};
void addShadersCommand(CLI::App& app, ShadersCommand& s);
int runShadersCommand(const ShadersCommand& s);

}  // namespace mrr
