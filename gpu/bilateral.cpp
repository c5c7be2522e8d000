#include "gpu/bilateral.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/program.h"
#include "gpu/stencil.h"

namespace mrr::gpu {

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
  ImageF out = target.read(0, 1);
  glDeleteTextures(1, &image);
  glDeleteTextures(1, &mask);
  return out;
}

}  // namespace mrr::gpu
