#include "gpu/blocks.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <string>

#include "gpu/program.h"

namespace mrr::gpu {

namespace {
// One blocks.frag pass into a fresh map (R8 targets, `outputs` of them) of width × height.
Target blockPass(const GpuScene& scene, const std::string& key, const std::string& defines, int width, int height,
                 std::initializer_list<std::pair<const char*, unsigned>> textures, int outputs = 1) {
  const unsigned program = scene.program("blocks." + key, "fullscreen.vert", "blocks.frag", defines);
  Target target = scene.target(width, height, std::vector<Texel>(static_cast<size_t>(outputs), Texel::R8), false);
  target->bind();
  glUseProgram(program);
  bindTextures(program, textures);
  scene.drawFullscreen();
  checkGl("blocks");
  return target;
}
}  // namespace

Target dilateBlocks(const GpuScene& scene, const BlockMap& map, int across, int down, const BlockMap& also) {
  const std::string shape = std::to_string(across) + "." + std::to_string(down) + (also ? ".u" : "");
  const std::string defines = "#define STEP 1\n#define DX " + std::to_string(across) + "\n#define DY " +
                              std::to_string(down) + "\n#define UNITE " + (also ? "1" : "0") + "\n";
  if (also) return blockPass(scene, "dilate." + shape, defines, map.width(), map.height(), {{"source", map.texture()}, {"also", also.texture()}});
  return blockPass(scene, "dilate." + shape, defines, map.width(), map.height(), {{"source", map.texture()}});
}

Target uniteBlocks(const GpuScene& scene, const BlockMap& a, const BlockMap& b) { return dilateBlocks(scene, a, 0, 0, b); }

Target poolBlocks(const GpuScene& scene, const BlockMap& map, int factor, int factorY) {
  if (factorY < 0) factorY = factor;
  return blockPass(scene, "pool." + std::to_string(factor) + "." + std::to_string(factorY),
                   "#define STEP 2\n#define FACTOR_X " + std::to_string(factor) + "\n#define FACTOR_Y " +
                       std::to_string(factorY) + "\n#define UNITE 0\n",
                   (map.width() + factor - 1) / factor, (map.height() + factorY - 1) / factorY, {{"source", map.texture()}});
}

std::vector<Target> blockMaps(const GpuScene& scene, const BlockMap& source, const BlockMap& fine,
                              const std::vector<MapSpec>& specs) {
  constexpr size_t kPerPass = 8;  // GL 3.3's draw buffers
  std::vector<Target> out;
  for (size_t first = 0; first < specs.size(); first += kPerPass) {
    const size_t n = std::min(kPerPass, specs.size() - first);
    int reachA = 0, reachB = -1;
    std::string defines = "#define STEP 3\n#define OUTPUTS " + std::to_string(n) + "\n";
    std::string key = "maps";
    for (size_t k = 0; k < kPerPass; ++k) {
      MapSpec m = k < n ? specs[first + k] : MapSpec{};
      reachA = std::max({reachA, m.ax, m.ay});
      reachB = std::max({reachB, m.bx, m.by});
      const std::string spec = "ivec4(" + std::to_string(m.ax) + ", " + std::to_string(m.ay) + ", " +
                               std::to_string(m.bx) + ", " + std::to_string(m.by) + ")";
      defines += "#define SPEC_" + std::to_string(k) + " " + spec + "\n";
      if (k < n) key += "." + std::to_string(m.ax) + "," + std::to_string(m.ay) + "," + std::to_string(m.bx) + "," + std::to_string(m.by);
    }
    const bool withFine = reachB >= 0;
    defines += "#define REACH_A " + std::to_string(reachA) + "\n#define REACH_B " + std::to_string(std::max(reachB, 0)) +
               "\n#define FINE " + (withFine ? "1" : "0") + "\n#define UNITE 0\n";
    if (withFine)
      out.push_back(blockPass(scene, key, defines, source.width(), source.height(),
                              {{"source", source.texture()}, {"fine", fine.texture()}}, static_cast<int>(n)));
    else
      out.push_back(blockPass(scene, key, defines, source.width(), source.height(), {{"source", source.texture()}},
                              static_cast<int>(n)));
  }
  return out;
}

}  // namespace mrr::gpu
