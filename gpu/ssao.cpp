#include "gpu/ssao.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/stencil.h"
#include "gpu/program.h"

namespace mrr::gpu {

ImageF renderSsao(const GpuScene& scene, const Framebuffer& gbuffer, const ImageU8& stencil, const View& view,
                  const LevelConstants& level, const Constants::Ssao& ssao) {
  Framebuffer target(level.width, level.height, 1, true);
  target.bind();
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  // 1. S_ℓ into the stencil buffer
  fillStencil(scene, stencil);
  // 2. the effect where the stencil is 1
  const unsigned kernel = uploadKernel(ssao.kernel);
  const unsigned program = scene.program("ssao", "fullscreen.vert", "ssao.frag");
  glUseProgram(program);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, gbuffer.texture(0));
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, gbuffer.texture(1));
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, kernel);
  glUniform1i(glGetUniformLocation(program, "positionHit"), 0);
  glUniform1i(glGetUniformLocation(program, "normalDepth"), 1);
  glUniform1i(glGetUniformLocation(program, "kernel"), 2);
  glUniform1i(glGetUniformLocation(program, "samples"), ssao.samples);
  glUniform1i(glGetUniformLocation(program, "level"), level.index);
  glUniform1f(glGetUniformLocation(program, "invScale"), 1.0f / static_cast<float>(level.scale));
  glUniform3f(glGetUniformLocation(program, "camera"), view.focal, view.cx, view.cy);
  glUniform1f(glGetUniformLocation(program, "radius"), ssao.radius);
  glUniform1f(glGetUniformLocation(program, "bias"), ssao.bias);
  glUniform1i(glGetUniformLocation(program, "tangentPlaneDepth"), ssao.tangentPlaneDepth ? 1 : 0);
  scene.drawFullscreen();
  glDisable(GL_STENCIL_TEST);
  checkGl("ssao");
  ImageF out = target.read(0, 1);
  glDeleteTextures(1, &kernel);
  return out;
}

std::vector<uint32_t> hashGrid(const GpuScene& scene, int width, int height, int level) {
  Framebuffer target(width, height, 1, false);
  target.bind();
  const unsigned program = scene.program("hash", "fullscreen.vert", "hash.frag");
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "level"), level);
  scene.drawFullscreen();
  checkGl("hash");
  const ImageF halves = target.read(0);
  std::vector<uint32_t> out(static_cast<size_t>(width) * height);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = (static_cast<uint32_t>(halves.data[4 * i]) << 16) | static_cast<uint32_t>(halves.data[4 * i + 1]);
  return out;
}

}  // namespace mrr::gpu
