#include "app/byo.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <iostream>

#include "common/error.h"
#include "common/hash.h"
#include "common/image_io.h"
#include "common/kernels.h"
#include "common/params.h"
#include "common/shader_contract.h"
#include "common/stages.h"
#include "compare/parity/against.h"
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

namespace {

// mrr's sampling as data (docs/spec.md §7.1), for a renderer that wants the oracle's
// exact numbers: the kernels at the default sample counts of seed 0 (JSON and a two-part EXR,
// one N x 1 RGB row each), and the rotation hash's definition with test vectors.
void writeSampling(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  require(std::filesystem::is_directory(dir, ec), "shaders export " + dir.string() + ": cannot make the folder");
  nlohmann::json j = {{"mrr_sampling", 1},
                      {"spec", "docs/spec.md 6 and 7.1"},
                      {"seed", 0},
                      {"kernel_generator",
                       "ssaoKernel(n, kernelSeed(base, seed)), kernelSeed(base, seed) = base + seed * 0x9e3779b9 "
                       "(uint32 wrap-around); common/kernels.cpp"},
                      {"rotation",
                       "angle = 2 pi hashToUnit(rotationHash(x, y, level, seed)), rotationHash = pixelHash(x, y, level + "
                       "4 seed), pixelHash(x, y, l) = pcg(x + pcg(y + pcg(l))), hashToUnit(h) = (h >> 8) / 2^24; "
                       "common/hash.h, cpu_ref/hemisphere.h sampleFrame"}};
  std::vector<ExrPart> parts;
  int widest = 1;
  const std::pair<const char*, uint32_t> kernels[] = {{"ssao", kSsaoKernelSeed}, {"ssgi", kSsgiKernelSeed}};
  for (const auto& [name, base] : kernels) {
    const int n = defaultSettings(std::string(name) == "ssao" ? Effect::Ssao : Effect::Ssgi).samples();
    const std::vector<glm::vec3> k = ssaoKernel(n, kernelSeed(base, 0));
    nlohmann::json points = nlohmann::json::array();
    ExrPart part{name, ImageF(n, 1, 3), {"R", "G", "B"}};
    for (int i = 0; i < n; ++i) {
      const glm::vec3& v = k[static_cast<size_t>(i)];
      points.push_back({v.x, v.y, v.z});
      for (int c = 0; c < 3; ++c) part.image.at(i, 0, c) = v[c];
    }
    j["kernels"][name] = {{"base_seed", base}, {"samples", n}, {"points", points}};
    widest = std::max(widest, n);
    parts.push_back(std::move(part));
  }
  nlohmann::json vectors = nlohmann::json::array();
  for (const auto& [x, y, level, seed] : {std::array<uint32_t, 4>{0, 0, 0, 0}, {3, 5, 2, 0}, {3, 5, 2, 1},
                                          {1279, 719, 0, 0}, {17, 9, 3, 12345}, {100, 50, 1, 1000000}}) {
    const uint32_t h = rotationHash(x, y, level, seed);
    vectors.push_back({{"x", x}, {"y", y}, {"level", level}, {"seed", seed}, {"hash", h},
                       {"angle", 6.28318530717958647692f * hashToUnit(h)}});
  }
  j["rotation_test_vectors"] = vectors;
  j["pcg_test_vectors"] = {{{"v", 0}, {"pcg", pcgHash(0u)}}, {{"v", 1}, {"pcg", pcgHash(1u)}}, {{"v", 12345}, {"pcg", pcgHash(12345u)}}};
  writeTextFile((dir / "sampling.json").string(), j.dump(1) + "\n");
  writeMultiPartExr((dir / "kernels.exr").string(), parts, widest, 1, {{"mrr:sampling", "seed 0; docs/spec.md 7.1"}});
}

}  // namespace

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
  writeSampling(std::filesystem::path(dir) / "sampling");
  std::cout << "wrote " << names.size() << " shaders, README.md and sampling/ (the kernels and the rotation hash) to "
            << dir << "\n";
  return 0;
}

}  // namespace mrr
