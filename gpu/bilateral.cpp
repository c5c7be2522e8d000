#include "gpu/bilateral.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/program.h"

namespace mrr::gpu {

void fillStencil(const GpuScene& scene, const ImageU8& stencil) {
  const unsigned mask = uploadTexture(toFloat(stencil));
  const unsigned fill = scene.program("stencil", "fullscreen.vert", "stencil.frag");
  glClearStencil(0);
  glClear(GL_STENCIL_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(fill);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, mask);
  glUniform1i(glGetUniformLocation(fill, "stencilMask"), 0);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  scene.drawFullscreen();
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glStencilFunc(GL_EQUAL, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  glDeleteTextures(1, &mask);
  checkGl("stencil");
}

ImageF bilateralBlur(const GpuScene& scene, const ImageF& raw, const ImageU8& stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b) {
  if (b.radius == 0) return raw;
  Framebuffer target(raw.width, raw.height, 1, true);
  target.bind();
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  fillStencil(scene, stencil);
  const unsigned image = uploadTexture(raw), mask = uploadTexture(toFloat(stencil));
  const unsigned program = scene.program("bilateral", "fullscreen.vert", "bilateral.frag");
  glUseProgram(program);
  const unsigned textures[4] = {image, mask, gbuffer.texture(0), gbuffer.texture(1)};
  const char* names[4] = {"image", "stencilMask", "positionHit", "normalDepth"};
  for (int i = 0; i < 4; ++i) {
    glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(i));
    glBindTexture(GL_TEXTURE_2D, textures[i]);
    glUniform1i(glGetUniformLocation(program, names[i]), i);
  }
  glUniform1i(glGetUniformLocation(program, "radius"), b.radius);
  glUniform1fv(glGetUniformLocation(program, "spatial"), static_cast<GLsizei>(b.spatial.size()), b.spatial.data());
  glUniform1f(glGetUniformLocation(program, "sigmaDepth"), b.sigmaDepth);
  glUniform1f(glGetUniformLocation(program, "normalPower"), b.normalPower);
  scene.drawFullscreen();
  glDisable(GL_STENCIL_TEST);
  checkGl("bilateral");
  const ImageF rgba = target.read(0);
  ImageF out(raw.width, raw.height);
  for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = rgba.data[4 * i];
  glDeleteTextures(1, &image);
  glDeleteTextures(1, &mask);
  return out;
}

}  // namespace mrr::gpu
