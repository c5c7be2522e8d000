#include "app/byo.h"

#include <filesystem>
#include <iostream>

#include "common/error.h"
#include "common/image_io.h"
#include "common/shader_contract.h"
#include "common/stages.h"
#include "compare/against.h"
#include "gpu/program.h"

namespace mrr {

void addShadersOption(CLI::App& command, std::string& dir) {
  command.add_option("--shaders", dir,
                     "the port with your own GLSL: each file of DIR (as `mrr shaders export` writes) replaces the "
                     "built-in shader of the same name; the built-ins serve the rest (docs/shader-contract.md)");
}

void useShaderDirectory(const std::string& dir, bool quiet) {
  if (dir.empty()) return;
  const gpu::ShaderDirectory d = gpu::loadShaderDirectory(dir);
  if (!d.unknown.empty()) {
    std::string known;
    for (const std::string& n : gpu::shaderFileNames()) known += (known.empty() ? "" : ", ") + n;
    for (const std::string& n : d.unknown)
      std::cerr << "mrr: warning: " << (std::filesystem::path(dir) / n).string()
                << " is no shader of mrr and is not used (mrr's shaders: " << known << ")\n";
  }
  std::string loaded;
  for (const std::string& n : d.loaded) loaded += (loaded.empty() ? "" : ", ") + n;
  if (quiet) return;
  if (d.loaded.empty())
    std::cerr << "[mrr] shaders: " << dir << " holds none of mrr's shader files; every shader is built in\n";
  else
    std::cerr << "[mrr] shaders from " << dir << ": " << loaded
              << (d.loaded.size() == gpu::shaderFileNames().size() ? " (every shader)\n" : " (built in: the rest)\n");
}

void addAgainstOption(CLI::App& command, std::string& file) {
  command.add_option("--against", file,
                     "another renderer's stages instead of the port: a multi-part EXR with the parts and channels "
                     "`render --stages` writes (any subset; final alone is enough), or a folder of PART.exr files");
}

void checkForeignStagesFile(const std::string& file, const std::string& effect) {
  std::error_code ec;
  require(std::filesystem::exists(file, ec), "--against " + file + ": no such file or folder");
  require(effect != "all", "--against " + file + ": one effect at a time (the file holds one frame's stages)");
  if (std::filesystem::is_directory(file, ec)) return;  // its files are named and read with the frame
  Part part;
  bool any = false;
  std::string names;
  for (const ExrPart& p : readParts(file)) {
    any = any || partOf(p.name, part);
    names += (names.empty() ? "" : ", ") + (p.name.empty() ? std::string("(unnamed)") : p.name);
  }
  require(any, "--against " + file + ": not a stages file: none of its parts (" + names +
                   ") is named like a stage of `mrr render --stages` (gbuffer.L0, edges, ..., final)");
}

std::string formatNotChecked(const ForeignStages& foreign) {
  if (foreign.absent.empty()) return {};
  std::string list;
  for (const std::string& n : foreign.absent) list += (list.empty() ? "" : ", ") + n;
  return "not checked (absent from " + foreign.source + "): " + list + "\n";
}

void addShadersCommand(CLI::App& app, ShadersCommand& s) {
  s.command = app.add_subcommand("shaders", "the port's shaders: export them to edit, or print their contract");
  s.command->require_subcommand(1);
  s.exportCommand = s.command->add_subcommand(
      "export", "write every shader of the port (stages and includes) and a README of the contract into DIR");
  s.exportCommand->add_option("DIR", s.exportDir, "the folder (made when missing)")->required();
  s.contractCommand = s.command->add_subcommand(
      "contract", "print docs/shader-contract.md: each shader's inputs, uniforms, outputs and the oracle's function");
}

int runShadersCommand(const ShadersCommand& s) {
  if (s.contractCommand->parsed()) {
    std::cout << shaderContractMarkdown();
    return 0;
  }
  const std::string& dir = s.exportDir;
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) std::filesystem::create_directories(dir, ec);
  require(std::filesystem::is_directory(dir, ec), "shaders export " + dir + ": cannot make the folder");
  const std::vector<std::string> names = gpu::shaderFileNames();
  for (const std::string& n : names) checkOutputLocation((std::filesystem::path(dir) / n).string(), "shaders export");
  for (const std::string& n : names)
    writeTextFile((std::filesystem::path(dir) / n).string(), gpu::builtinShaderSource(n));
  writeTextFile((std::filesystem::path(dir) / "README.md").string(), shaderExportReadme());
  std::cout << "wrote " << names.size() << " shaders and README.md to " << dir << "\n";
  return 0;
}

}  // namespace mrr
