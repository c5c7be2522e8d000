#include "gpu/blend.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "gpu/masks.h"
#include "gpu/program.h"

namespace mrr::gpu {

namespace {

// FINAL_ONLY: every level in one full-res pass, only the final image and level map.
// One FINAL_ONLY variant: `fine` is the set of finer levels it blends (a bit each);
// `coarsestCovered`: the coarsest level's S is 1 on its whole grid (drawn masks); drawn over
// `rects`, or the whole frame when null.
void drawFinalOnly(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, const Constants& c,
                   int fine, bool coarsestCovered, const Cover& cover) {
  // The levels and the coarsest's scale are constants of the variant, so bilinearTap's
  // division by the scale is by a known power of two.
  const int coarsest = c.coarsestEnabled;
  const std::string variant = "#define FINAL_ONLY\n#define FINE_LEVELS " + std::to_string(fine) +
                              "\n#define COARSEST_LEVEL " + std::to_string(coarsest) + "\n#define COARSEST_SCALE " +
                              std::to_string(c.levels[static_cast<size_t>(coarsest)].scale) + "\n" +
                              (coarsestCovered ? "#define COARSEST_COVERED\n" : "");
  const unsigned program = scene.passProgram("blend.final." + std::to_string(fine) + "." + std::to_string(coarsest) +
                                                 (coarsestCovered ? ".covered" : ""),
                                             "blend.frag", variant, cover);
  glUseProgram(program);
  const LevelTextures& base = levels[static_cast<size_t>(coarsest)];
  bindTextures(program, {{"subC", base.sub}, {"stencilC", base.stencil}});
  int unit = 3;
  for (int l = 0; l < 3; ++l) {
    if (!(fine & (1 << l))) continue;
    const LevelTextures& in = levels[static_cast<size_t>(l)];
    const std::string L = std::to_string(l);
    bindTextures(program, {{("sub" + L).c_str(), in.sub}, {("stencil" + L).c_str(), in.stencil}, {("alpha" + L).c_str(), in.alpha}},
                 unit);
    unit += 3;
  }
  const float weights[3] = {c.levels[0].weight, c.levels[1].weight, c.levels[2].weight};
  if (fine) glUniform1fv(uniform(program, "weights"), 3, weights);  // without finer levels, nothing reads them
  scene.draw(cover, c.width, c.height);
}

BlendResult blendFinalOnly(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, int channels,
                           const Constants& c, const BlockMap& nearBlocks, GpuImage* finalOnGpu) {
  int fine = 0;  // the enabled levels finer than C, a bit each (the shader's FINE_LEVELS)
  for (int l = 0; l < c.coarsestEnabled; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled) fine |= 1 << l;
  Target target = scene.target(c.width, c.height, {effectTexel(channels), Texel::R8}, false);
  target->bind();
  if (nearBlocks && fine) {
    // Near an edge, every level; far from every edge, the coarsest alone (MaskTargets::blendNear:
    // beyond a finer level's reach its α is 0, and blendStep(0, f, c) = c). The near and the far
    // pass are drawn over the map's set and its clear runs. (Blocks split by which levels reach
    // them draw more, smaller rectangles, and measured slower on llvmpipe.)
    const int blockSize = 1 << (kLevelCount - 1);  // full-res pixels per block
    drawFinalOnly(scene, levels, c, fine, true, Cover::blocksOf(nearBlocks, blockSize, 1));
    drawFinalOnly(scene, levels, c, 0, true, Cover::blocksOf(nearBlocks, blockSize, 0));
  } else {
    drawFinalOnly(scene, levels, c, fine, static_cast<bool>(nearBlocks), Cover::whole());
  }
  checkGl("blend");
  if (finalOnGpu) *finalOnGpu = {std::move(target), 0};  // the level map beside it, in target 1
  return {};
}

}  // namespace

BlendResult blendLevels(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, int channels,
                        const Constants& c, bool keepStages, const BlockMap& nearBlocks, GpuImage* finalOnGpu) {
  if (!keepStages) return blendFinalOnly(scene, levels, channels, c, nearBlocks, finalOnGpu);
  const unsigned program = scene.program("blend", "fullscreen.vert", "blend.frag");
  const Texel color = effectTexel(channels);
  BlendResult r;
  Target previous;
  for (int l = c.coarsestEnabled; l >= 0; --l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const LevelTextures& in = levels[static_cast<size_t>(l)];
    // ĉ_ℓ, α_ℓ, c'_ℓ and the level map (the finest level with α > 0, as on the host)
    Target target = scene.target(c.width, c.height, {color, Texel::R32f, color, Texel::R8}, false);
    target->bind();
    glUseProgram(program);
    bindTextures(program, {{"sub", in.sub},
                           {"stencilMask", in.stencil},
                           {"alphaMask", in.alpha},
                           {"coarser", previous ? previous->texture(2) : in.sub},
                           {"coarserLevel", previous ? previous->texture(3) : in.stencil}});
    glUniform1i(uniform(program, "coarsest"), previous ? 0 : 1);
    glUniform1i(uniform(program, "level"), l);
    glUniform1i(uniform(program, "scale"), lc.scale);
    glUniform1f(uniform(program, "weight"), lc.weight);
    scene.drawFullscreen();
    checkGl("blend");
    r.upsampled[static_cast<size_t>(l)] = target->read(0, channels);
    r.alpha[static_cast<size_t>(l)] = target->read(1, 1);
    r.composite[static_cast<size_t>(l)] = target->read(2, channels);
    previous = std::move(target);
  }
  r.final = r.composite[static_cast<size_t>(c.finestEnabled)];
  r.levelMap = previous->readBytes(3);
  if (finalOnGpu) *finalOnGpu = {std::move(previous), 2};  // c'_finest
  return r;
}

Target blendReach(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, const Constants& c,
                  const BlockMap& nearBlocks) {
  int fine = 0;  // the enabled levels finer than C, a bit each (FINE_LEVELS)
  for (int l = 0; l < c.coarsestEnabled; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled) fine |= 1 << l;
  const int coarsest = c.coarsestEnabled;
  // Near an edge the pass; far from every edge no finer α can be > 0 (MaskTargets::blendNear, as
  // the final-only blend's far pass), so R = C there: the target is cleared to it. (Outside W×H
  // a far block then holds C, not 0, but trim.frag reads R inside W×H alone.)
  const Cover cover = nearBlocks && fine ? Cover::blocksOf(nearBlocks, 1 << (kLevelCount - 1), 1) : Cover::whole();
  const unsigned program = scene.passProgram("blend.reach." + std::to_string(fine) + "." + std::to_string(coarsest),
                                             "blend.frag",
                                             "#define REACH\n#define FINE_LEVELS " + std::to_string(fine) +
                                                 "\n#define COARSEST_LEVEL " + std::to_string(coarsest) + "\n",
                                             cover);
  const LevelConstants& l0 = c.levels[0];
  Target target = scene.target(l0.width, l0.height, {Texel::R8}, false);
  target->bind();
  if (!cover.isWhole()) {
    const float far[4] = {static_cast<float>(coarsest) / 255.0f, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, far);
  }
  glUseProgram(program);
  int unit = 0;
  for (int l = 0; l < 3; ++l) {
    if (!(fine & (1 << l))) continue;
    const LevelTextures& in = levels[static_cast<size_t>(l)];
    const std::string L = std::to_string(l);
    bindTextures(program, {{("stencil" + L).c_str(), in.stencil}, {("alpha" + L).c_str(), in.alpha}}, unit);
    unit += 2;
  }
  const float weights[3] = {c.levels[0].weight, c.levels[1].weight, c.levels[2].weight};
  if (fine) glUniform1fv(uniform(program, "weights"), 3, weights);
  glUniform2i(uniform(program, "frame"), c.width, c.height);
  scene.draw(cover, l0.width, l0.height);
  checkGl("blend reach");
  return target;
}

}  // namespace mrr::gpu
