#include "gpu/blend.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <memory>

#include "gpu/program.h"

namespace mrr::gpu {

namespace {

// FINAL_ONLY: every level in one full-res pass, only the final image and level map.
BlendResult blendFinalOnly(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, int channels,
                           const Constants& c) {
  const unsigned program = scene.program("blend.final", "fullscreen.vert", "blend.frag", "#define FINAL_ONLY\n");
  Framebuffer target(c.width, c.height, std::vector<Texel>{effectTexel(channels), Texel::R8}, false);
  target.bind();
  glUseProgram(program);
  const LevelTextures& base = levels[static_cast<size_t>(c.coarsestEnabled)];
  auto orBase = [&](unsigned t, unsigned fallback) { return t ? t : fallback; };  // disabled levels: never read
  bindTextures(program, {{"sub0", orBase(levels[0].sub, base.sub)},
                         {"sub1", orBase(levels[1].sub, base.sub)},
                         {"sub2", orBase(levels[2].sub, base.sub)},
                         {"sub3", orBase(levels[3].sub, base.sub)},
                         {"stencil0", orBase(levels[0].stencil, base.stencil)},
                         {"stencil1", orBase(levels[1].stencil, base.stencil)},
                         {"stencil2", orBase(levels[2].stencil, base.stencil)},
                         {"stencil3", orBase(levels[3].stencil, base.stencil)},
                         {"alpha0", orBase(levels[0].alpha, base.alpha)},
                         {"alpha1", orBase(levels[1].alpha, base.alpha)},
                         {"alpha2", orBase(levels[2].alpha, base.alpha)},
                         {"alpha3", orBase(levels[3].alpha, base.alpha)}});
  GLint enabled[kLevelCount];
  float weights[kLevelCount];
  for (size_t l = 0; l < kLevelCount; ++l) {
    enabled[l] = c.levels[l].enabled ? 1 : 0;
    weights[l] = c.levels[l].weight;
  }
  glUniform1iv(glGetUniformLocation(program, "enabledLevel"), kLevelCount, enabled);
  glUniform1fv(glGetUniformLocation(program, "weights"), kLevelCount, weights);
  glUniform1i(glGetUniformLocation(program, "coarsestLevel"), c.coarsestEnabled);
  scene.drawFullscreen();
  checkGl("blend");
  BlendResult r;
  r.final = target.read(0, channels);
  r.levelMap = target.readBytes(1);
  return r;
}

}  // namespace

BlendResult blendLevels(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, int channels,
                        const Constants& c, bool keepStages) {
  if (!keepStages) return blendFinalOnly(scene, levels, channels, c);
  const unsigned program = scene.program("blend", "fullscreen.vert", "blend.frag");
  const Texel color = effectTexel(channels);
  BlendResult r;
  Target previous;
  for (int l = c.coarsestEnabled; l >= 0; --l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const LevelTextures& in = levels[static_cast<size_t>(l)];
    // ĉ_ℓ, α_ℓ, c'_ℓ and the level map (the finest level with α > 0, as on the host)
    auto target = std::make_unique<Framebuffer>(c.width, c.height, std::vector<Texel>{color, Texel::R32f, color, Texel::R8},
                                                false);
    target->bind();
    glUseProgram(program);
    bindTextures(program, {{"sub", in.sub},
                           {"stencilMask", in.stencil},
                           {"alphaMask", in.alpha},
                           {"coarser", previous ? previous->texture(2) : in.sub},
                           {"coarserLevel", previous ? previous->texture(3) : in.stencil}});
    glUniform1i(glGetUniformLocation(program, "coarsest"), previous ? 0 : 1);
    glUniform1i(glGetUniformLocation(program, "level"), l);
    glUniform1i(glGetUniformLocation(program, "scale"), lc.scale);
    glUniform1f(glGetUniformLocation(program, "weight"), lc.weight);
    scene.drawFullscreen();
    checkGl("blend");
    r.upsampled[static_cast<size_t>(l)] = target->read(0, channels);
    r.alpha[static_cast<size_t>(l)] = target->read(1, 1);
    r.composite[static_cast<size_t>(l)] = target->read(2, channels);
    previous = std::move(target);
  }
  r.final = r.composite[static_cast<size_t>(c.finestEnabled)];
  r.levelMap = previous->readBytes(3);
  return r;
}

}  // namespace mrr::gpu
