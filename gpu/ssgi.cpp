#include "gpu/ssgi.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/program.h"
#include "gpu/shadowmap.h"
#include "gpu/stencil.h"

namespace mrr::gpu {

void drawDirectLight(const GpuScene& scene, const Framebuffer& gbuffer, const ShadowMap& map, unsigned mapTexture,
                     const View& view, const DirectionalLight& light, float biasTexels, const Framebuffer& target) {
  const unsigned program = scene.program("direct", "fullscreen.vert", "ssgi.frag", "#define DIRECT_LIGHT\n");
  target.bind();
  glUseProgram(program);
  const char* names[3] = {"positionHit", "normalDepth", "albedo"};
  for (int i = 0; i < 3; ++i) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(i));
    glBindTexture(GL_TEXTURE_2D, gbuffer.texture(i));
    glUniform1i(glGetUniformLocation(program, names[i]), i);
  }
  bindShadowMap(program, map, mapTexture, 3, view, biasTexels);
  // the same expression as the oracle's directLight, so both shade with the same bits
  const glm::vec3 toLight = -glm::normalize(view.directionToView(light.direction));
  glUniform3f(glGetUniformLocation(program, "toLight"), toLight.x, toLight.y, toLight.z);
  glUniform3f(glGetUniformLocation(program, "lightColor"), light.color.x, light.color.y, light.color.z);
  scene.drawFullscreen();
  checkGl("direct");
}

ImageF directLight(const GpuScene& scene, const Framebuffer& gbuffer, const ShadowMap& map, unsigned mapTexture,
                   const View& view, const DirectionalLight& light, float biasTexels) {
  const Framebuffer target(gbuffer.width(), gbuffer.height(), 1, false);
  drawDirectLight(scene, gbuffer, map, mapTexture, view, light, biasTexels, target);
  return target.read(0, 3);
}

ImageF renderSsgi(const GpuScene& scene, const Framebuffer& gbuffer, unsigned directTexture, const ImageU8& stencil,
                  const View& view, const LevelConstants& level, const Constants::Ssgi& ssgi) {
  Framebuffer target(level.width, level.height, 1, true);
  target.bind();
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  // 1. S_ℓ into the stencil buffer
  fillStencil(scene, stencil);
  // 2. the gather where the stencil is 1
  const unsigned kernel = uploadKernel(ssgi.kernel);
  const unsigned program = scene.program("ssgi", "fullscreen.vert", "ssgi.frag");
  glUseProgram(program);
  const unsigned textures[4] = {gbuffer.texture(0), gbuffer.texture(1), directTexture, kernel};
  const char* names[4] = {"positionHit", "normalDepth", "direct", "kernel"};
  for (int i = 0; i < 4; ++i) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(i));
    glBindTexture(GL_TEXTURE_2D, textures[i]);
    glUniform1i(glGetUniformLocation(program, names[i]), i);
  }
  glUniform1i(glGetUniformLocation(program, "samples"), ssgi.samples);
  glUniform1i(glGetUniformLocation(program, "level"), level.index);
  glUniform1f(glGetUniformLocation(program, "invScale"), 1.0f / static_cast<float>(level.scale));
  glUniform3f(glGetUniformLocation(program, "camera"), view.focal, view.cx, view.cy);
  glUniform1f(glGetUniformLocation(program, "radius"), ssgi.radius);
  glUniform1f(glGetUniformLocation(program, "patchArea"), ssgi.patchArea);
  glUniform1f(glGetUniformLocation(program, "minDistance2"), ssgi.minDistance2);
  scene.drawFullscreen();
  glDisable(GL_STENCIL_TEST);
  checkGl("ssgi");
  ImageF out = target.read(0, 3);
  glDeleteTextures(1, &kernel);
  return out;
}

}  // namespace mrr::gpu
