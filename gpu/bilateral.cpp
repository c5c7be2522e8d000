#include "gpu/bilateral.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/program.h"
#include "gpu/stencil.h"

namespace mrr::gpu {

ImageF bilateralBlur(const GpuScene& scene, const ImageF& raw, const ImageU8& stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b) {
  if (b.radius == 0) return raw;
  const unsigned image = uploadTexture(raw), mask = uploadTexture(toFloat(stencil));
  const unsigned program = scene.program("bilateral", "fullscreen.vert", "bilateral.frag");
  ImageF out = drawStencilled(scene, stencil, program, 1, "bilateral", [&] {
    bindTextures(program, {{"image", image},
                           {"stencilMask", mask},
                           {"positionHit", gbuffer.texture(0)},
                           {"normalDepth", gbuffer.texture(1)}});
    glUniform1i(glGetUniformLocation(program, "radius"), b.radius);
    glUniform1fv(glGetUniformLocation(program, "spatial"), static_cast<GLsizei>(b.spatial.size()), b.spatial.data());
    glUniform1f(glGetUniformLocation(program, "sigmaDepth"), b.sigmaDepth);
    glUniform1f(glGetUniformLocation(program, "normalPower"), b.normalPower);
  });
  glDeleteTextures(1, &image);
  glDeleteTextures(1, &mask);
  return out;
}

}  // namespace mrr::gpu
