#include "gpu/ssao.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/stencil.h"
#include "gpu/program.h"

namespace mrr::gpu {

Target drawSsao(const GpuScene& scene, const Framebuffer& gbuffer, unsigned stencil, const View& view,
                const LevelConstants& level, const Constants::Ssao& ssao,
                const Cover& fill) {
  TextureSet kernel;
  const unsigned kernelTexture = kernel.add(uploadKernel(ssao.kernel));
  const unsigned program = scene.program("ssao", "fullscreen.vert", "ssao.frag");
  return drawStencilled(scene, stencil, gbuffer.width(), gbuffer.height(), Texel::R32f, program, "ssao", [&] {
    bindTextures(program,
                 {{"positionHit", gbuffer.texture(0)}, {"normalDepth", gbuffer.texture(1)}, {"kernel", kernelTexture}});
    setLevelUniforms(program, view, level);
    glUniform1i(uniform(program, "samples"), ssao.samples);
    glUniform1f(uniform(program, "radius"), ssao.radius);
    glUniform1f(uniform(program, "bias"), ssao.bias);
    glUniform1i(uniform(program, "tangentPlaneDepth"), ssao.tangentPlaneDepth ? 1 : 0);
    // Optional: a user's shader written before --seed (or with its own noise) may not read it.
    if (const int seedAt = glGetUniformLocation(program, "seed"); seedAt >= 0) glUniform1ui(seedAt, ssao.seed);
  }, fill);
}

ImageF renderSsao(const GpuScene& scene, const Framebuffer& gbuffer, const ImageU8& stencil, const View& view,
                  const LevelConstants& level, const Constants::Ssao& ssao) {
  return withHostStencil(stencil, 1, [&](unsigned s) { return drawSsao(scene, gbuffer, s, view, level, ssao); });
}

std::vector<uint32_t> hashGrid(const GpuScene& scene, int width, int height, int level) {
  const Target targetPtr = scene.target(width, height, 1, false);
  const Framebuffer& target = *targetPtr;
  target.bind();
  const unsigned program = scene.program("hash", "fullscreen.vert", "hash.frag");
  glUseProgram(program);
  glUniform1i(uniform(program, "level"), level);
  scene.drawFullscreen();
  checkGl("hash");
  const ImageF halves = target.read(0);
  std::vector<uint32_t> out(static_cast<size_t>(width) * height);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = (static_cast<uint32_t>(halves.data[4 * i]) << 16) | static_cast<uint32_t>(halves.data[4 * i + 1]);
  return out;
}

}  // namespace mrr::gpu
