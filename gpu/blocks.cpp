#include "gpu/blocks.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "gpu/program.h"

namespace mrr::gpu {

namespace {
// One blocks.frag pass into a fresh R8 map of width × height.
Target blockPass(const GpuScene& scene, const std::string& key, const std::string& defines, int width, int height,
                 unsigned source, unsigned also) {
  const unsigned program = scene.program("blocks." + key, "fullscreen.vert", "blocks.frag", defines);
  Target target = scene.target(width, height, 1, false, Texel::R8);
  target->bind();
  glUseProgram(program);
  bindTextures(program, {{"source", source}});
  if (also) bindTextures(program, {{"also", also}}, 1);
  scene.drawFullscreen();
  checkGl("blocks");
  return target;
}
}  // namespace

Target dilateBlocks(const GpuScene& scene, const Framebuffer& map, int across, int down, const Framebuffer* also) {
  const std::string shape = std::to_string(across) + "." + std::to_string(down) + (also ? ".u" : "");
  return blockPass(scene, "dilate." + shape,
                   "#define STEP 1\n#define DX " + std::to_string(across) + "\n#define DY " + std::to_string(down) +
                       "\n#define UNITE " + (also ? "1" : "0") + "\n",
                   map.width(), map.height(), map.texture(0), also ? also->texture(0) : 0);
}

Target uniteBlocks(const GpuScene& scene, const Framebuffer& a, const Framebuffer& b) {
  return dilateBlocks(scene, a, 0, 0, &b);
}

Target poolBlocks(const GpuScene& scene, const Framebuffer& map, int factor, int factorY) {
  if (factorY < 0) factorY = factor;
  return blockPass(scene, "pool." + std::to_string(factor) + "." + std::to_string(factorY),
                   "#define STEP 2\n#define FACTOR_X " + std::to_string(factor) + "\n#define FACTOR_Y " +
                       std::to_string(factorY) + "\n#define UNITE 0\n",
                   (map.width() + factor - 1) / factor, (map.height() + factorY - 1) / factorY, map.texture(0), 0);
}

}  // namespace mrr::gpu
