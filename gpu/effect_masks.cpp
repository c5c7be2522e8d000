#include "gpu/effect_masks.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>
#include <vector>

#include "gpu/masks.h"
#include "gpu/program.h"
#include "gpu/shadowmap.h"

namespace mrr::gpu {

namespace {
// Draws the bound program over `rects` (null: every pixel) of the bound target, the rest of it
// cleared to `outside` (what the pass gives there).
void drawOver(const GpuScene& scene, const std::vector<glm::ivec4>* rects, int width, int height, float outside) {
  if (!rects) return scene.drawFullscreen();
  const float clear[4] = {outside, outside, outside, outside};
  glClearBufferfv(GL_COLOR, 0, clear);
  scene.drawRects(*rects, width, height);
}
// A pass's program in use over a fresh width × height target of `texel`, with its textures bound
// (units 0, 1, ...): the caller sets its uniforms and draws (drawOver).
Target startPass(const GpuScene& scene, unsigned program, int width, int height, Texel texel,
                 std::initializer_list<std::pair<const char*, unsigned>> textures) {
  Target target = scene.target(width, height, 1, false, texel);
  target->bind();
  glUseProgram(program);
  bindTextures(program, textures);
  return target;
}
}  // namespace

Target drawFootprint(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned edges, int edgeChannel,
                     const ShadowMap* map, unsigned mapTexture, const View& view, const Constants& c,
                     const std::vector<glm::ivec4>* rects) {
  const bool ssm = c.effect == Effect::Ssm;
  const std::string defines = "#define STEP 1\n#define EDGE_CHANNEL " + std::to_string(edgeChannel) +
                              "\n#define EFFECT_SSM " + (ssm ? "1" : "0") + "\n";
  const unsigned program = scene.program("effect_masks.1." + std::to_string(edgeChannel) + (ssm ? ".ssm" : ""),
                                         "fullscreen.vert", "effect_masks.frag", defines);
  Target target =
      startPass(scene, program, gbuffer0.width(), gbuffer0.height(), Texel::R32f,
                {{"positionHit", gbuffer0.texture(0)}, {"normalDepth", gbuffer0.texture(1)}, {"edges", edges}});
  if (ssm) {
    bindShadowMap(program, *map, mapTexture, 3, view, c.ssm.biasTexels);
    glUniform1f(uniform(program, "tanHalfAngle"), c.ssm.tanHalfAngle);
  } else {
    glUniform1f(uniform(program, "reach"), c.effect == Effect::Ssao ? c.ssao.radius : c.ssgi.radius);
  }
  glUniform1f(uniform(program, "focal"), view.focal);
  glUniform1f(uniform(program, "scale"), c.effectMask.scale);
  drawOver(scene, rects, gbuffer0.width(), gbuffer0.height(), 0.0f);
  checkGl("effect_masks footprint");
  return target;
}

Target drawDilateByReach(const GpuScene& scene, unsigned mask, int maskChannel, unsigned footprint, int width,
                         int height, int levelScale, int cap, const std::vector<glm::ivec4>* across,
                         const std::vector<glm::ivec4>* within) {
  const std::string shape =
      "#define CAP " + std::to_string(cap) + "\n#define MASK_CHANNEL " + std::to_string(maskChannel) + "\n";
  const std::string key = std::to_string(cap) + "." + std::to_string(maskChannel);
  // 1. reach and the pass along x: H as float (−1: no reach)
  const unsigned acrossProgram =
      scene.program("effect_masks.2." + key, "fullscreen.vert", "effect_masks.frag", "#define STEP 2\n" + shape);
  Target h = startPass(scene, acrossProgram, width, height, Texel::R32f, {{"source", mask}, {"footprint", footprint}});
  glUniform1f(uniform(acrossProgram, "levelScale"), static_cast<float>(levelScale));
  drawOver(scene, across, width, height, -1.0f);
  checkGl("effect_masks across");
  // 2. the pass along y: M'_ℓ
  const unsigned down =
      scene.program("effect_masks.3." + key, "fullscreen.vert", "effect_masks.frag", "#define STEP 3\n" + shape);
  Target widened = startPass(scene, down, width, height, Texel::R8, {{"source", h->texture(0)}});
  drawOver(scene, within, width, height, 0.0f);
  checkGl("effect_masks down");
  return widened;
}

Target drawWideningOnly(const GpuScene& scene, unsigned widened, unsigned mask, int maskChannel, int width, int height,
                        const std::vector<glm::ivec4>* within) {
  const unsigned program =
      scene.program("effect_masks.4." + std::to_string(maskChannel), "fullscreen.vert", "effect_masks.frag",
                    "#define STEP 4\n#define MASK_CHANNEL " + std::to_string(maskChannel) + "\n");
  // 1. the pixels the widening adds: M'_ℓ ∧ ¬M_ℓ
  Target only = startPass(scene, program, width, height, Texel::R8, {{"source", widened}, {"geometry", mask}});
  drawOver(scene, within, width, height, 0.0f);
  checkGl("effect_masks widening only");
  return only;
}

Target drawRangeTest(const GpuScene& scene, unsigned coarser, int channels, unsigned coarserStencil,
                     unsigned coarserPositionHit, float tau, const std::vector<glm::ivec4>* shaded, bool rangeOut,
                     bool whole) {
  int width = 0, height = 0;  // the coarser level's grid
  glBindTexture(GL_TEXTURE_2D, coarser);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &height);
  const std::vector<glm::ivec4>* rects = shaded && !shaded->empty() ? shaded : nullptr;  // no mark off S_n
  const std::string shape = "#define STEP 1\n#define CHANNELS " + std::to_string(channels) + "\n#define RANGE_OUT " +
                            (rangeOut ? "1" : "0") + "\n";
  const std::string key = std::to_string(channels) + (rangeOut ? ".range" : "");
  const Texel out = rangeOut ? Texel::R32f : Texel::R8;
  const float outside = rangeOut ? -1.0f : 0.0f;
  if (whole) {
    // 1. v(q) over each whole 3×3 (the readable form)
    const unsigned program = scene.program("refinement_marks.1.0." + key, "fullscreen.vert", "refinement_marks.frag",
                                           shape + "#define PASS 0\n");
    Target t = startPass(scene, program, width, height, out,
                         {{"source", coarser}, {"stencil", coarserStencil}, {"positionHit", coarserPositionHit}});
    glUniform1f(uniform(program, "tau"), tau);
    drawOver(scene, rects, width, height, outside);
    checkGl("refinement_marks whole");
    return t;
  }
  // 1a. along x: each channel's min and max over the row of three
  const unsigned across = scene.program("refinement_marks.1.1." + key, "fullscreen.vert", "refinement_marks.frag",
                                        shape + "#define PASS 1\n");
  Target extremes = scene.target(width, height, {Texel::Rgba32f, Texel::Rgba32f}, false);
  extremes->bind();
  glUseProgram(across);
  bindTextures(across, {{"source", coarser}, {"stencil", coarserStencil}, {"positionHit", coarserPositionHit}});
  glUniform1f(uniform(across, "tau"), tau);
  scene.drawFullscreen();  // every pixel: a row's neighbours off S_n still read their (neutral) extremes
  checkGl("refinement_marks across");
  // 1b. along y: v, then [v > τ] or v
  const unsigned down = scene.program("refinement_marks.1.2." + key, "fullscreen.vert", "refinement_marks.frag",
                                      shape + "#define PASS 2\n");
  Target t = startPass(scene, down, width, height, out,
                       {{"source", extremes->texture(0)}, {"maxima", extremes->texture(1)}, {"stencil", coarserStencil},
                        {"positionHit", coarserPositionHit}});
  glUniform1f(uniform(down, "tau"), tau);
  drawOver(scene, rects, width, height, outside);
  checkGl("refinement_marks down");
  return t;
}

Target drawParentMarks(const GpuScene& scene, unsigned varies, int ratio, int finerWidth, int finerHeight,
                       const std::vector<glm::ivec4>* rects) {
  // 2. each finer pixel takes its coarser parent's mark
  const unsigned parent =
      scene.program("refinement_marks.2." + std::to_string(ratio), "fullscreen.vert", "refinement_marks.frag",
                    "#define STEP 2\n#define RATIO " + std::to_string(ratio) + "\n");
  Target marks = startPass(scene, parent, finerWidth, finerHeight, Texel::R8, {{"source", varies}});
  if (rects && rects->empty()) {  // no mark: nothing to draw
    const float zero[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, zero);
  } else {
    drawOver(scene, rects, finerWidth, finerHeight, 0.0f);
  }
  checkGl("refinement_marks parent");
  return marks;
}

std::vector<glm::ivec4> markedRects(const ImageU8& blocks, int blockSize, int ratio, int coarserWidth, int coarserHeight,
                                    int finerWidth, int finerHeight) {
  std::vector<glm::ivec4> rects;  // the finer level's pixels in the blocks holding a mark
  for (const auto& run : blockRects(blocks, 1, blockSize, coarserWidth, coarserHeight))  // coarser pixels → finer
    rects.push_back(glm::min(run * ratio, glm::ivec4(finerWidth, finerHeight, finerWidth, finerHeight)));
  return rects;
}

Target drawRefinementMarks(const GpuScene& scene, unsigned coarser, int channels, unsigned coarserStencil,
                           unsigned coarserPositionHit, int ratio, int finerWidth, int finerHeight, float tau,
                           const std::vector<glm::ivec4>* shaded, ImageU8* blocks, int blockSize) {
  // 1. v(q) > τ at each coarser pixel q, over the shaded hit pixels of its 3×3 neighbourhood
  const Target coarse = drawRangeTest(scene, coarser, channels, coarserStencil, coarserPositionHit, tau, shaded, false);
  if (!blocks) return drawParentMarks(scene, coarse->texture(0), ratio, finerWidth, finerHeight, nullptr);
  // 2. each finer pixel takes its coarser parent's mark, drawn over the blocks holding one
  *blocks = blocksOf(coarse->readBinary(0), blockSize);
  const std::vector<glm::ivec4> rects =
      markedRects(*blocks, blockSize, ratio, coarse->width(), coarse->height(), finerWidth, finerHeight);
  return drawParentMarks(scene, coarse->texture(0), ratio, finerWidth, finerHeight, &rects);
}

}  // namespace mrr::gpu
