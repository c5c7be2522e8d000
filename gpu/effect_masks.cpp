#include "gpu/effect_masks.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>
#include <vector>

#include "common/effect_budget.h"
#include "common/shader_constants.h"
#include "gpu/blocks.h"
#include "gpu/masks.h"
#include "gpu/program.h"
#include "gpu/shadowmap.h"

namespace mrr::gpu {

namespace {
// Draws the bound program over `cover` of the bound target, the rest of it cleared to `outside`
// (what the pass gives there).
void drawOver(const GpuScene& scene, const Cover& cover, int width, int height, float outside) {
  if (cover.isWhole()) return scene.drawFullscreen();
  const float clear[4] = {outside, outside, outside, outside};
  glClearBufferfv(GL_COLOR, 0, clear);
  scene.draw(cover, width, height);
}
// A pass's program in use over a fresh width × height target of `texels` (one a target), with its
// textures bound (units 0, 1, ...): the caller sets its uniforms and draws (drawOver).
Target startPass(const GpuScene& scene, unsigned program, int width, int height, const std::vector<Texel>& texels,
                 std::initializer_list<std::pair<const char*, unsigned>> textures) {
  Target target = scene.target(width, height, texels, false);
  target->bind();
  glUseProgram(program);
  bindTextures(program, textures);
  return target;
}
}  // namespace

Target drawFootprint(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned edges, int edgeChannel,
                     const ShadowMap* map, unsigned mapTexture, const View& view, const Constants& c,
                     const Cover& cover) {
  const bool ssm = c.effect == Effect::Ssm;
  const std::string defines = "#define STEP 1\n#define EDGE_CHANNEL " + std::to_string(edgeChannel) +
                              "\n#define EFFECT_SSM " + (ssm ? "1" : "0") + "\n";
  const unsigned program = scene.passProgram("effect_masks.1." + std::to_string(edgeChannel) + (ssm ? ".ssm" : ""),
                                             "effect_masks.frag", defines, cover);
  Target target =
      startPass(scene, program, gbuffer0.width(), gbuffer0.height(), {Texel::R32f},
                {{"positionHit", gbuffer0.texture(0)}, {"normalDepth", gbuffer0.texture(1)}, {"edges", edges}});
  if (ssm) {
    bindShadowMap(program, *map, mapTexture, 3, view, c.ssm.biasTexels);
    glUniform1f(uniform(program, "tanHalfAngle"), c.ssm.tanHalfAngle);
  } else {
    glUniform1f(uniform(program, "reach"), c.effect == Effect::Ssao ? c.ssao.radius : c.ssgi.radius);
  }
  glUniform1f(uniform(program, "focal"), view.focal);
  glUniform1f(uniform(program, "scale"), c.effectMask.scale);
  drawOver(scene, cover, gbuffer0.width(), gbuffer0.height(), 0.0f);
  checkGl("effect_masks footprint");
  return target;
}

Target drawDilateByReach(const GpuScene& scene, unsigned mask, int maskChannel, unsigned footprint, int width,
                         int height, int levelScale, int cap, const Cover& across, const Cover& within) {
  const std::string shape =
      "#define CAP " + std::to_string(cap) + "\n#define MASK_CHANNEL " + std::to_string(maskChannel) + "\n";
  const std::string key = std::to_string(cap) + "." + std::to_string(maskChannel);
  // 1. reach and the pass along x: H as float (−1: no reach)
  const unsigned acrossProgram = scene.passProgram("effect_masks.2." + key, "effect_masks.frag", "#define STEP 2\n" + shape, across);
  Target h = startPass(scene, acrossProgram, width, height, {Texel::R32f}, {{"source", mask}, {"footprint", footprint}});
  glUniform1f(uniform(acrossProgram, "levelScale"), static_cast<float>(levelScale));
  drawOver(scene, across, width, height, -1.0f);
  checkGl("effect_masks across");
  // 2. the pass along y: M'_ℓ
  const unsigned down = scene.passProgram("effect_masks.3." + key, "effect_masks.frag", "#define STEP 3\n" + shape, within);
  Target widened = startPass(scene, down, width, height, {Texel::R8}, {{"source", h->texture(0)}});
  drawOver(scene, within, width, height, 0.0f);
  checkGl("effect_masks down");
  return widened;
}

Target drawWideningOnly(const GpuScene& scene, unsigned widened, unsigned mask, int maskChannel, int width, int height,
                        const Cover& within) {
  const unsigned program = scene.passProgram("effect_masks.4." + std::to_string(maskChannel), "effect_masks.frag",
                                             "#define STEP 4\n#define MASK_CHANNEL " + std::to_string(maskChannel) + "\n",
                                             within);
  // 1. the pixels the widening adds: M'_ℓ ∧ ¬M_ℓ
  Target only = startPass(scene, program, width, height, {Texel::R8}, {{"source", widened}, {"geometry", mask}});
  drawOver(scene, within, width, height, 0.0f);
  checkGl("effect_masks widening only");
  return only;
}

Target drawRangeTest(const GpuScene& scene, unsigned coarser, int channels, unsigned coarserStencil,
                     unsigned coarserPositionHit, float tau, const Cover& shaded, bool rangeOut, bool whole) {
  int width = 0, height = 0;  // the coarser level's grid
  glBindTexture(GL_TEXTURE_2D, coarser);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
  glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &height);
  const std::string shape = "#define STEP 1\n#define CHANNELS " + std::to_string(channels) + "\n#define RANGE_OUT " +
                            (rangeOut ? "1" : "0") + "\n";
  const std::string key = std::to_string(channels) + (rangeOut ? ".range" : "");
  const Texel out = rangeOut ? Texel::R32f : Texel::R8;
  const float outside = rangeOut ? -1.0f : 0.0f;  // no mark off S_n
  if (whole) {
    // 1. v(q) over each whole 3×3 (the readable form)
    const unsigned program =
        scene.passProgram("refinement_marks.1.0." + key, "refinement_marks.frag", shape + "#define PASS 0\n", shaded);
    Target t = startPass(scene, program, width, height, {out},
                         {{"source", coarser}, {"stencil", coarserStencil}, {"positionHit", coarserPositionHit}});
    if (!rangeOut) glUniform1f(uniform(program, "tau"), tau);
    drawOver(scene, shaded, width, height, outside);
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
  scene.drawFullscreen();  // every pixel: a row's neighbours off S_n still read their (neutral) extremes
  checkGl("refinement_marks across");
  // 1b. along y: v, then [v > τ] or v
  const unsigned down =
      scene.passProgram("refinement_marks.1.2." + key, "refinement_marks.frag", shape + "#define PASS 2\n", shaded);
  Target t = startPass(scene, down, width, height, {out},
                       {{"source", extremes->texture(0)}, {"maxima", extremes->texture(1)}, {"stencil", coarserStencil},
                        {"positionHit", coarserPositionHit}});
  if (!rangeOut) glUniform1f(uniform(down, "tau"), tau);  // v itself: τ is the host's
  drawOver(scene, shaded, width, height, outside);
  checkGl("refinement_marks down");
  return t;
}

namespace {
// Step 2's pass: each finer pixel takes its coarser parent's mark in `varies`, over `marked`.
Target drawParent(const GpuScene& scene, unsigned varies, int ratio, int finerWidth, int finerHeight,
                  const Cover& marked) {
  const unsigned parent = scene.passProgram("refinement_marks.2." + std::to_string(ratio), "refinement_marks.frag",
                                            "#define STEP 2\n#define RATIO " + std::to_string(ratio) + "\n", marked);
  Target marks = startPass(scene, parent, finerWidth, finerHeight, {Texel::R8}, {{"source", varies}});
  drawOver(scene, marked, finerWidth, finerHeight, 0.0f);
  checkGl("refinement_marks parent");
  return marks;
}
}  // namespace

Target drawParentMarks(const GpuScene& scene, Target varies, int ratio, int finerWidth, int finerHeight, Target* blocks,
                       int blockSize) {
  // the blocks holding a mark, on the GPU (blocksOf): the finer level's pixels in them are
  // blockSize · ratio a side
  Cover marked;
  if (blocks) {
    *blocks = blockSize > 1 ? poolBlocks(scene, *varies, blockSize) : std::move(varies);
    marked = Cover::blocksOf(**blocks, blockSize * ratio);
  }
  // 2. each finer pixel takes its coarser parent's mark
  const unsigned source = varies ? varies->texture(0) : (*blocks)->texture(0);  // blockSize 1: the marks are their blocks
  return drawParent(scene, source, ratio, finerWidth, finerHeight, marked);
}

Target drawRefinementMarks(const GpuScene& scene, unsigned coarser, int channels, unsigned coarserStencil,
                           unsigned coarserPositionHit, int ratio, int finerWidth, int finerHeight, float tau,
                           const Cover& shaded, Target* blocks, int blockSize) {
  // 1. v(q) > τ at each coarser pixel q, over the shaded hit pixels of its 3×3 neighbourhood
  Target varies = drawRangeTest(scene, coarser, channels, coarserStencil, coarserPositionHit, tau, shaded, false);
  // 2. each finer pixel takes its coarser parent's mark
  return drawParentMarks(scene, std::move(varies), ratio, finerWidth, finerHeight, blocks, blockSize);
}

namespace {
constexpr int kBudgetFactor = 16;  // candidates a side per fragment of STEP 5, totals of STEP 6
unsigned budgetProgram(const GpuScene& scene, const std::string& key, const std::string& defines) {
  return scene.program("refinement_budget." + key, "fullscreen.vert", "refinement_budget.frag", defines);
}
}  // namespace

BudgetedSelection drawBudgetedSelection(const GpuScene& scene, unsigned range, unsigned finerStencil,
                                        unsigned positionHit0, unsigned pcfSample, const Constants& c, int level,
                                        int coarser, const RefinementRecord& r, const Framebuffer* before) {
  const LevelConstants& fine = c.levels[static_cast<size_t>(level)];
  const LevelConstants& coarse = c.levels[static_cast<size_t>(coarser)];
  const int ratio = 1 << (coarser - level);
  const std::string shape = "#define RATIO " + std::to_string(ratio) + "\n";
  const std::vector<Texel> one = {Texel::Rgba32ui}, four(4, Texel::Rgba32ui);
  BudgetedSelection out;
  // 2a–b. each level-ℓ pixel's price, summed down its candidates' windows
  const bool pcf = pcfSample != 0;
  const unsigned down = budgetProgram(scene, "2." + std::to_string(ratio) + (pcf ? ".pcf" : ""),
                                      "#define STEP 2\n#define PCF_SAMPLE " + std::string(pcf ? "1" : "0") + "\n" + shape);
  Target columns = startPass(scene, down, fine.width, coarse.height, one,
                             {{"stencil", finerStencil}, {"positionHit", positionHit0}});
  if (pcf) bindTextures(down, {{"pcfSample", pcfSample}}, 2);
  glUniform3ui(uniform(down, "prices"), r.units.paying, r.units.pcf, r.units.leaving);
  glUniform1i(uniform(down, "levelScale"), fine.scale);
  glUniform1i(uniform(down, "radius"), fine.blurRadius);
  scene.drawFullscreen();
  checkGl("refinement_budget window");
  // 2c, 3. the prices along the windows' columns, and the candidates' keys
  TextureSet uploaded;
  const bool sticky = c.effectMask.hysteresis > 0.0f && r.previousMarked.width == coarse.width &&
                      r.previousMarked.height == coarse.height;
  // uploaded before the pass binds its textures (an upload binds on the active unit)
  const unsigned previous = sticky ? uploaded.add(uploadBinary(r.previousMarked)) : 0;
  const unsigned keys = budgetProgram(scene, "3." + std::to_string(ratio) + (sticky ? ".h" : ""),
                                      "#define STEP 3\n#define HYSTERESIS " + std::string(sticky ? "1" : "0") + "\n" + shape);
  out.candidates = startPass(scene, keys, coarse.width, coarse.height, one,
                             {{"columns", columns->texture(0)}, {"range", range}});
  glUniform1i(uniform(keys, "radius"), fine.blurRadius);
  glUniform1f(uniform(keys, "tau"), c.effectMask.posterior);
  if (sticky) {
    bindTextures(keys, {{"previous", previous}}, 2);
    glUniform1f(uniform(keys, "keepTau"), (1.0f - c.effectMask.hysteresis) * c.effectMask.posterior);
    glUniform1ui(uniform(keys, "bonus"), hysteresisBonus(c.effectMask.hysteresis));
  }
  scene.drawFullscreen();
  checkGl("refinement_budget keys");
  columns.reset();
  // 4. the level's state: its share of what is left
  const bool chained = before != nullptr;
  const unsigned begin = budgetProgram(scene, std::string("4.") + (chained ? "chained" : "first"),
                                       "#define STEP 4\n#define CHAINED " + std::string(chained ? "1" : "0") + "\n");
  out.state = startPass(scene, begin, 1, 1, one, {});
  glUniform1i(uniform(begin, "levelsLeft"), r.levelsLeft);
  if (chained) bindTextures(begin, {{"before", before->texture(0)}});
  else glUniform1ui(uniform(begin, "budget"), r.leftUnits);
  scene.drawFullscreen();
  // 4a–b. the threshold, kBudgetRadix keys a round: the totals at each, summed to one texel, and
  // the least that fits
  const std::string factor = "#define FACTOR " + std::to_string(kBudgetFactor) + "\n";
  const unsigned reduce = budgetProgram(scene, "6", "#define STEP 6\n" + factor);
  const unsigned totals = budgetProgram(scene, "5", "#define STEP 5\n" + factor);
  const unsigned decide = budgetProgram(scene, "7", "#define STEP 7\n");
  for (int stride = kBudgetKeys / kBudgetRadix; stride >= 1; stride /= kBudgetRadix) {
    int w = (coarse.width + kBudgetFactor - 1) / kBudgetFactor, h = (coarse.height + kBudgetFactor - 1) / kBudgetFactor;
    Target sums = startPass(scene, totals, w, h, four,
                            {{"state", out.state->texture(0)}, {"candidates", out.candidates->texture(0)}});
    glUniform1i(uniform(totals, "stride"), stride);
    scene.drawFullscreen();
    while (w > 1 || h > 1) {
      w = (w + kBudgetFactor - 1) / kBudgetFactor;
      h = (h + kBudgetFactor - 1) / kBudgetFactor;
      sums = startPass(scene, reduce, w, h, four,
                       {{"values0", sums->texture(0)}, {"values1", sums->texture(1)}, {"values2", sums->texture(2)},
                        {"values3", sums->texture(3)}});
      scene.drawFullscreen();
    }
    out.state = startPass(scene, decide, 1, 1, one,
                          {{"state", out.state->texture(0)}, {"values0", sums->texture(0)}, {"values1", sums->texture(1)},
                           {"values2", sums->texture(2)}, {"values3", sums->texture(3)}});
    glUniform1i(uniform(decide, "stride"), stride);
    scene.drawFullscreen();
    checkGl("refinement_budget threshold");
  }
  // 4c. the marks
  const unsigned mark = budgetProgram(scene, "8", "#define STEP 8\n");
  out.marks = startPass(scene, mark, coarse.width, coarse.height, {Texel::R8},
                        {{"candidates", out.candidates->texture(0)}, {"state", out.state->texture(0)}});
  scene.drawFullscreen();
  checkGl("refinement_budget marks");
  return out;
}

Target drawBudgetCounts(const GpuScene& scene, const BudgetedSelection& s) {
  const unsigned program = budgetProgram(scene, "9", "#define STEP 9\n");
  Target t = startPass(scene, program, s.candidates->width(), s.candidates->height(), {Texel::Rgba32ui},
                       {{"candidates", s.candidates->texture(0)}, {"state", s.state->texture(0)}});
  scene.drawFullscreen();
  checkGl("refinement_budget counts");
  return t;
}

}  // namespace mrr::gpu
