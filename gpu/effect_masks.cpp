#include "gpu/effect_masks.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "gpu/program.h"
#include "gpu/shadowmap.h"

namespace mrr::gpu {

Target drawFootprint(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned edges, int edgeChannel,
                     const ShadowMap* map, unsigned mapTexture, const View& view, const Constants& c) {
  const bool ssm = c.effect == Effect::Ssm;
  const std::string defines = "#define STEP 1\n#define EDGE_CHANNEL " + std::to_string(edgeChannel) +
                              "\n#define EFFECT_SSM " + (ssm ? "1" : "0") + "\n";
  const unsigned program = scene.program("effect_masks.1." + std::to_string(edgeChannel) + (ssm ? ".ssm" : ""),
                                         "fullscreen.vert", "effect_masks.frag", defines);
  Target target = scene.target(gbuffer0.width(), gbuffer0.height(), 1, false, Texel::R32f);
  target->bind();
  glUseProgram(program);
  bindTextures(program, {{"positionHit", gbuffer0.texture(0)}, {"normalDepth", gbuffer0.texture(1)}, {"edges", edges}});
  if (ssm) {
    bindShadowMap(program, *map, mapTexture, 3, view, c.ssm.biasTexels);
    glUniform1f(uniform(program, "tanHalfAngle"), c.ssm.tanHalfAngle);
  } else {
    glUniform1f(uniform(program, "reach"), c.effect == Effect::Ssao ? c.ssao.radius : c.ssgi.radius);
  }
  glUniform1f(uniform(program, "focal"), view.focal);
  glUniform1f(uniform(program, "scale"), c.effectMask.scale);
  scene.drawFullscreen();
  checkGl("effect_masks footprint");
  return target;
}

Target drawDilateByReach(const GpuScene& scene, unsigned mask, int maskChannel, unsigned footprint, int width,
                         int height, int levelScale, int cap) {
  const std::string shape = "#define CAP " + std::to_string(cap) + "\n#define MASK_CHANNEL " +
                            std::to_string(maskChannel) + "\n";
  const std::string key = std::to_string(cap) + "." + std::to_string(maskChannel);
  // 1. reach and the pass along x: H as float (−1: no reach)
  const unsigned across = scene.program("effect_masks.2." + key, "fullscreen.vert", "effect_masks.frag",
                                        "#define STEP 2\n" + shape);
  Target h = scene.target(width, height, 1, false, Texel::R32f);
  h->bind();
  glUseProgram(across);
  bindTextures(across, {{"source", mask}, {"footprint", footprint}});
  glUniform1f(uniform(across, "levelScale"), static_cast<float>(levelScale));
  scene.drawFullscreen();
  checkGl("effect_masks across");
  // 2. the pass along y: M'_ℓ
  const unsigned down = scene.program("effect_masks.3." + key, "fullscreen.vert", "effect_masks.frag",
                                      "#define STEP 3\n" + shape);
  Target widened = scene.target(width, height, 1, false, Texel::R8);
  widened->bind();
  glUseProgram(down);
  bindTextures(down, {{"source", h->texture(0)}});
  scene.drawFullscreen();
  checkGl("effect_masks down");
  return widened;
}

Target drawWideningOnly(const GpuScene& scene, unsigned widened, unsigned mask, int maskChannel, int width,
                        int height) {
  const unsigned program = scene.program("effect_masks.4." + std::to_string(maskChannel), "fullscreen.vert",
                                         "effect_masks.frag",
                                         "#define STEP 4\n#define MASK_CHANNEL " + std::to_string(maskChannel) + "\n");
  // 1. the pixels the widening adds: M'_ℓ ∧ ¬M_ℓ
  Target only = scene.target(width, height, 1, false, Texel::R8);
  only->bind();
  glUseProgram(program);
  bindTextures(program, {{"source", widened}, {"geometry", mask}});
  scene.drawFullscreen();
  checkGl("effect_masks widening only");
  return only;
}

Target drawRefinementMarks(const GpuScene& scene, unsigned coarser, int channels, unsigned coarserStencil,
                           unsigned coarserPositionHit, int ratio, int finerWidth, int finerHeight, float tau) {
  int width = 0, height = 0;  // the coarser level's grid
  glBindTexture(GL_TEXTURE_2D, coarser);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &height);
  // 1. v(q) > τ at each coarser pixel q, over the shaded hit pixels of its 3×3 neighbourhood
  const unsigned varies = scene.program("refinement_marks.1." + std::to_string(channels), "fullscreen.vert",
                                        "refinement_marks.frag",
                                        "#define STEP 1\n#define CHANNELS " + std::to_string(channels) + "\n");
  Target coarse = scene.target(width, height, 1, false, Texel::R8);
  coarse->bind();
  glUseProgram(varies);
  bindTextures(varies, {{"source", coarser}, {"stencil", coarserStencil}, {"positionHit", coarserPositionHit}});
  glUniform1f(uniform(varies, "tau"), tau);
  scene.drawFullscreen();
  checkGl("refinement_marks varies");
  // 2. each finer pixel takes its coarser parent's mark
  const unsigned parent = scene.program("refinement_marks.2." + std::to_string(ratio), "fullscreen.vert",
                                        "refinement_marks.frag",
                                        "#define STEP 2\n#define RATIO " + std::to_string(ratio) + "\n");
  Target marks = scene.target(finerWidth, finerHeight, 1, false, Texel::R8);
  marks->bind();
  glUseProgram(parent);
  bindTextures(parent, {{"source", coarse->texture(0)}});
  scene.drawFullscreen();
  checkGl("refinement_marks parent");
  return marks;
}

}  // namespace mrr::gpu
