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

}  // namespace mrr::gpu
