#include "gpu/stencil.h"

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
  bindTextures(fill, {{"stencilMask", mask}});
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

ImageF drawStencilled(const GpuScene& scene, const ImageU8& stencil, unsigned program, int channels,
                      const std::string& stage, const std::function<void()>& setInputs) {
  Framebuffer target(stencil.width, stencil.height, 1, true);
  target.bind();
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  // 1. S_ℓ into the stencil buffer
  fillStencil(scene, stencil);
  // 2. the pass where the stencil is 1
  glUseProgram(program);
  setInputs();
  scene.drawFullscreen();
  glDisable(GL_STENCIL_TEST);
  checkGl(stage);
  return target.read(0, channels);
}

}  // namespace mrr::gpu
