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
  bindTextures(program,
               {{"positionHit", gbuffer.texture(0)}, {"normalDepth", gbuffer.texture(1)}, {"albedo", gbuffer.texture(2)}});
  bindShadowMap(program, map, mapTexture, 3, view, biasTexels);
  // the same expression as the oracle's directLight, so both shade with the same bits
  const glm::vec3 toLight = -glm::normalize(view.directionToView(light.direction));
  glUniform3f(uniform(program, "toLight"), toLight.x, toLight.y, toLight.z);
  glUniform3f(uniform(program, "lightColor"), light.color.x, light.color.y, light.color.z);
  scene.drawFullscreen();
  checkGl("direct");
}

ImageF directLight(const GpuScene& scene, const Framebuffer& gbuffer, const ShadowMap& map, unsigned mapTexture,
                   const View& view, const DirectionalLight& light, float biasTexels) {
  const Target target = scene.target(gbuffer.width(), gbuffer.height(), 1, false);
  drawDirectLight(scene, gbuffer, map, mapTexture, view, light, biasTexels, *target);
  return target->read(0, 3);
}

Target drawSsgi(const GpuScene& scene, const Framebuffer& gbuffer, unsigned directTexture, unsigned stencil,
                const View& view, const LevelConstants& level, const Constants::Ssgi& ssgi,
                const Cover& fill) {
  TextureSet kernel;
  const unsigned kernelTexture = kernel.add(uploadKernel(ssgi.kernel));
  const unsigned program = scene.program("ssgi", "fullscreen.vert", "ssgi.frag");
  return drawStencilled(scene, stencil, gbuffer.width(), gbuffer.height(), Texel::Rgba32f, program, "ssgi", [&] {
    bindTextures(program, {{"positionHit", gbuffer.texture(0)},
                           {"normalDepth", gbuffer.texture(1)},
                           {"direct", directTexture},
                           {"kernel", kernelTexture}});
    setLevelUniforms(program, view, level);
    glUniform1i(uniform(program, "samples"), ssgi.samples);
    glUniform1f(uniform(program, "radius"), ssgi.radius);
    glUniform1f(uniform(program, "patchArea"), ssgi.patchArea);
    glUniform1f(uniform(program, "minDistance2"), ssgi.minDistance2);
    // Optional: a user's shader written before --seed (or with its own noise) may not read it.
    if (const int seedAt = glGetUniformLocation(program, "seed"); seedAt >= 0) glUniform1ui(seedAt, ssgi.seed);
  }, fill);
}

ImageF renderSsgi(const GpuScene& scene, const Framebuffer& gbuffer, unsigned directTexture, const ImageU8& stencil,
                  const View& view, const LevelConstants& level, const Constants::Ssgi& ssgi) {
  return withHostStencil(stencil, 3,
                         [&](unsigned s) { return drawSsgi(scene, gbuffer, directTexture, s, view, level, ssgi); });
}

}  // namespace mrr::gpu
