#include "gpu/bilateral.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/program.h"
#include "gpu/stencil.h"

namespace mrr::gpu {

Target drawBilateral(const GpuScene& scene, unsigned raw, unsigned stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b, const Framebuffer* rawTarget) {
  if (b.radius == 0) return nullptr;
  const unsigned program = scene.program("bilateral", "fullscreen.vert", "bilateral.frag");
  auto setInputs = [&] {
    bindTextures(program, {{"image", raw},
                           {"stencilMask", stencil},
                           {"positionHit", gbuffer.texture(0)},
                           {"normalDepth", gbuffer.texture(1)}});
    glUniform1i(uniform(program, "radius"), b.radius);
    glUniform1fv(uniform(program, "spatial"), static_cast<GLsizei>(b.spatial.size()), b.spatial.data());
    glUniform1f(uniform(program, "sigmaDepth"), b.sigmaDepth);
    glUniform1f(uniform(program, "normalPower"), b.normalPower);
  };
  if (rawTarget) return drawStencilledLike(scene, *rawTarget, Texel::R32f, program, "bilateral", setInputs);
  return drawStencilled(scene, stencil, gbuffer.width(), gbuffer.height(), Texel::R32f, program, "bilateral", setInputs);
}

ImageF bilateralBlur(const GpuScene& scene, const ImageF& raw, const ImageU8& stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b) {
  if (b.radius == 0) return raw;
  TextureSet uploaded;
  const unsigned image = uploaded.add(uploadTexture(raw));
  return withHostStencil(stencil, 1, [&](unsigned s) { return drawBilateral(scene, image, s, gbuffer, b); });
}

}  // namespace mrr::gpu
