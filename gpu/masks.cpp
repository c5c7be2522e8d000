#include "gpu/masks.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/error.h"
#include "gpu/blend.h"
#include "gpu/blocks.h"
#include "gpu/effect_masks.h"
#include "gpu/program.h"

namespace mrr::gpu {

namespace {

struct Pass {
  const GpuScene& scene;
  struct Inputs {
    unsigned source = 0, previous = 0;
    int sourceChannel = 0, factor = 1;
    glm::ivec2 direction{1, 0};
    const std::vector<float>* weights = nullptr;
    bool withStencil = false;
    Cover cover;         // where it is drawn (the rest: 0)
    unsigned limit = 0;  // step 5: limit.frag's target
    int level = 0;       // step 5: ℓ
  };
  // The step's program, compiled once per pass shape: its parameters are constants in the
  // shader (masks.frag), so its loops unroll.
  unsigned program(int step, const Inputs& in) const {
    const int radius = in.weights ? static_cast<int>(in.weights->size() / 2) : 0;
    const std::string defines = "#define STEP " + std::to_string(step) + "\n#define FACTOR " +
                                std::to_string(in.factor) + "\n#define RADIUS " + std::to_string(radius) +
                                "\n#define DIRECTION ivec2(" + std::to_string(in.direction.x) + ", " +
                                std::to_string(in.direction.y) + ")\n#define SOURCE_CHANNEL " +
                                std::to_string(in.sourceChannel) + "\n#define WITH_STENCIL " +
                                (in.withStencil ? "1" : "0") + "\n#define LEVEL " + std::to_string(in.level) + "\n";
    const std::string name = "masks." + std::to_string(step) + "." + std::to_string(in.factor) + "." +
                             std::to_string(radius) + "." + std::to_string(in.direction.x) + "." +
                             std::to_string(in.sourceChannel) + "." + (in.withStencil ? "s" : "-") + "." +
                             std::to_string(in.level);
    return scene.passProgram(name, "masks.frag", defines, in.cover);
  }
  // One step into a fresh framebuffer of the given size and target formats, cleared to 0.
  Target run(int step, const std::vector<Texel>& formats, int width, int height, const Inputs& in) const {
    Target target = scene.target(width, height, formats, false);
    draw(step, *target, in, true);
    return target;
  }
  // One step into `target`, over in.cover; with `clear`, the rest 0, else kept.
  void draw(int step, const Framebuffer& target, const Inputs& in, bool clear) const {
    const unsigned prog = program(step, in);
    const int width = target.width(), height = target.height();
    target.bind();
    glUseProgram(prog);
    if (in.weights)
      glUniform1fv(uniform(prog, "weights"), static_cast<GLsizei>(in.weights->size()), in.weights->data());
    bindTextures(prog, {{"source", in.source}});
    if (step == 4) bindTextures(prog, {{"previous", in.previous}}, 1);
    if (step == 5) bindTextures(prog, {{"limit", in.limit}}, 1);
    if (!in.cover.isWhole() && clear) {
      const float zero[4] = {0, 0, 0, 0};
      for (int i = 0; i < target.targetCount(); ++i) glClearBufferfv(GL_COLOR, static_cast<GLint>(i), zero);
    }
    scene.draw(in.cover, width, height);
    checkGl("masks");
  }
};

// A target cleared to `value` (the coarsest enabled level's a = S = 1).
Target constantTarget(const GpuScene& scene, int width, int height, Texel format, float value) {
  Target target = scene.target(width, height, 1, false, format);
  target->bind();
  const float v[4] = {value, value, value, value};
  glClearBufferfv(GL_COLOR, 0, v);
  return target;
}

}  // namespace

ImageU8 blocksOf(const ImageU8& mask, int blockSize) {
  ImageU8 blocks((mask.width + blockSize - 1) / blockSize, (mask.height + blockSize - 1) / blockSize);
  for (int y = 0; y < mask.height; ++y)
    for (int x = 0; x < mask.width; ++x) blocks.at(x / blockSize, y / blockSize) |= mask.at(x, y);
  return blocks;
}

std::vector<glm::ivec4> blockRects(const ImageU8& blocks, uint8_t value, int blockSize, int width, int height) {
  // Row runs of matching blocks; a run with the same ends as one in the row above extends it,
  // so a band along an edge is a few rectangles, not one per block row.
  std::vector<glm::ivec4> rects;
  std::map<std::pair<int, int>, size_t> open, next;  // (x0, x1) in blocks → rect ending at this row
  for (int y = 0; y < blocks.height; ++y) {
    next.clear();
    for (int x = 0; x < blocks.width;) {
      if ((blocks.at(x, y) != 0) != (value != 0)) {
        ++x;
        continue;
      }
      int end = x;
      while (end < blocks.width && (blocks.at(end, y) != 0) == (value != 0)) ++end;
      const int y1 = std::min((y + 1) * blockSize, height);
      const auto above = open.find({x, end});
      if (above != open.end()) {
        rects[above->second].w = y1;
        next[{x, end}] = above->second;
      } else {
        const glm::ivec4 r(x * blockSize, y * blockSize, std::min(end * blockSize, width), y1);
        if (r.x < r.z && r.y < r.w) {
          next[{x, end}] = rects.size();
          rects.push_back(r);
        }
      }
      x = end;
    }
    open.swap(next);
  }
  return rects;
}

Cover MaskTargets::supportCover(int level) const {
  const BlockMap& blocks = supportBlocks[static_cast<size_t>(level)];
  return level == 0 && blocks ? Cover::blocksOf(blocks, 1 << (kLevelCount - 1)) : Cover::whole();
}

BlockMap MaskTargets::keep(Target map) {
  blockMaps.push_back(std::move(map));
  return BlockMap(*blockMaps.back());
}

std::unique_ptr<MaskTargets> drawMasks(const GpuScene& scene, unsigned edges, int edgeChannel, const Constants& c,
                                       const FootprintFn& footprint, unsigned limit) {
  const Pass pass{scene};
  auto out = std::make_unique<MaskTargets>();
  out->drawn = true;
  auto& mask = out->maskTarget;
  auto& stencil = out->stencilTarget;
  constexpr int kCoarsest = kLevelCount - 1;
  static_assert(kLevelCount == 4, "the pyramid below is written for levels 0–3");
  auto level = [&](int l) -> const LevelConstants& { return c.levels[static_cast<size_t>(l)]; };
  // 1. mask pyramid: M_0 = E (read in place), M_ℓ = maxpool2(M_{ℓ−1}), through disabled levels
  // too. M_2 first, straight from E (a 4×4 max-pool is the max-pool of 2×2 max-pools), then
  // M_1 and M_3. M_2's and M_3's texels are the block maps of E on the 4×4 and the 8×8 grid
  // (which blocks hold an edge: gpu/blocks.h); they stay on the GPU. Level 0's passes below,
  // which have work only near an edge, are drawn over the runs of maps made from them. The
  // coarser levels' passes are drawn whole: they hold a quarter of level 0's pixels or fewer.
  // Covering level 1 too (its blur, stencil fill, closure) gave the same bits and saved 0.5–0.7 ms
  // of a warm 720p frame's masks on llvmpipe, but its five more programs with blocks.geom made a
  // cold `mrr render` 1.8% slower (docs/port.md, "Where a frame's time goes"). Either way a pass
  // writes the same bits: a cover holds every pixel where the pass can be non-zero.
  auto maxPool = [&](int l, unsigned source, int channel, int factor) {
    Pass::Inputs in;
    in.source = source;
    in.sourceChannel = channel;
    in.factor = factor;
    mask[static_cast<size_t>(l)] = pass.run(1, {Texel::R8}, level(l).width, level(l).height, in);
  };
  maxPool(2, edges, edgeChannel, 4);
  maxPool(3, mask[2]->texture(0), 0, 2);
  const BlockMap fineBlocks(*mask[kCoarsest - 1]);  // the 4×4 grid's edge blocks (M_2)
  const BlockMap edgeBlocks(*mask[kCoarsest]);      // the 8×8 grid's (M_3)
  out->edgeBlocks = edgeBlocks;
  maxPool(1, edges, edgeChannel, 2);

  // 1a. Every block map the passes below are drawn over, in two passes (gpu/blocks.h blockMaps):
  // level 0's on the 4×4 grid (its support is narrow), the others' on the 8×8 one, each a box
  // dilation of E's blocks (nearBlocks: ceil(r / blockSize) blocks), boxes about one block
  // composing into one: M_ℓ's blocks, widened by mrr-effect's cap (SPEC §12) along x then y; the
  // blur's, r_ℓ further along x, then y; S_ℓ's, the union of every finer enabled level's (the
  // closure); and the blend's near blocks, within a finer level's reach.
  const auto blockSize = [](int l) { return l == 0 ? 1 << (kCoarsest - 1) : 1 << (kCoarsest - l); };
  // a level-0 pass's cover; a coarser level's passes are drawn whole (step 1)
  const auto cover = [&](const BlockMap& blocks, int l) {
    return l == 0 ? Cover::blocksOf(blocks, blockSize(l)) : Cover::whole();
  };
  const int cap = c.effectMask.cap;
  struct LevelMaps {
    bool blurred = false, widened = false;
    int capBlocks = 0, blurBlocks = 0;  // cap and r_ℓ in blocks of the level's grid
    int acrossCap = -1, within = -1, across = -1, near = -1, support = -1;  // indices into the maps
  };
  std::array<LevelMaps, kLevelCount> lm;
  std::vector<MapSpec> fine, coarse;  // the 4×4 grid's maps (level 0), the 8×8 grid's
  int supportA = -1, supportB = -1;   // the closure so far: its reach in 8×8 blocks, and level 0's in 4×4 ones
  int blendReach = 0;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = level(l);
    LevelMaps& m = lm[static_cast<size_t>(l)];
    if (!lc.enabled || l == c.coarsestEnabled) continue;
    m.blurred = true;
    m.widened = footprint && l >= c.effectMask.firstLevel;
    m.capBlocks = m.widened ? blocksWithin(cap, blockSize(l)) : 0;
    m.blurBlocks = blocksWithin(static_cast<int>(lc.gaussian.size() / 2), blockSize(l));
    const int k = m.capBlocks, r = m.capBlocks + m.blurBlocks;
    std::vector<MapSpec>& grid = l == 0 ? fine : coarse;
    const auto add = [&](MapSpec spec) {
      grid.push_back(spec);
      return static_cast<int>(grid.size()) - 1;
    };
    const auto along = [](int x, int y) { return MapSpec{x, y, -1, -1}; };
    if (m.widened) {
      if (l == 0) m.acrossCap = add(along(k, 0));
      m.within = add(along(k, k));  // M'_ℓ's blocks: the a-posteriori term's (refineMasks)
    }
    if (l == 0) {  // the blur's covers (a coarser level's blur is drawn whole)
      m.across = add(along(r, k));
      m.near = add(along(r, r));
    }
    if (l == 0) supportB = r;
    else supportA = std::max(supportA, r);
    m.support = static_cast<int>(coarse.size());
    coarse.push_back({supportA, supportA, supportB, supportB});  // S_ℓ's: every enabled level's so far
    blendReach = std::max(blendReach, (static_cast<int>(lc.gaussian.size() / 2) + (m.widened ? cap : 0) + 2) * lc.scale);
  }
  // level 0 widened: M'_0's blocks on the 8×8 grid (refineMasks' maskBlocks[0])
  const int pooledWithin0 = lm[0].widened ? static_cast<int>(coarse.size()) : -1;
  if (lm[0].widened) coarse.push_back({-1, -1, lm[0].capBlocks, lm[0].capBlocks});
  // the blend's near blocks (blendFinalOnly): a finer α is 0 beyond its reach (and 1 more pixel)
  const int blendNear = static_cast<int>(coarse.size());
  coarse.push_back({blocksWithin(blendReach, 1 << kCoarsest), blocksWithin(blendReach, 1 << kCoarsest), -1, -1});
  std::vector<Target> fineMaps = fine.empty() ? std::vector<Target>() : blockMaps(scene, fineBlocks, fineBlocks, fine);
  std::vector<Target> coarseMaps = blockMaps(scene, edgeBlocks, fineBlocks, coarse);
  const auto mapOf = [](const std::vector<Target>& maps, int index) {
    return index < 0 ? BlockMap() : BlockMap(*maps[static_cast<size_t>(index / 8)], index % 8);
  };
  const auto levelMap = [&](int l, int index) { return mapOf(l == 0 ? fineMaps : coarseMaps, index); };
  out->blendNear = mapOf(coarseMaps, blendNear);

  // 1b. mrr-effect (SPEC §12, gpu/effect_masks.cpp): F_ℓ = maxpool2(F_{ℓ−1}); each enabled level's
  // M_ℓ but the coarsest, from ℓ_first on, widened by its reach into M'_ℓ. The pyramid above
  // stays E's own. F is 0 off the edges, so F_ℓ is drawn over the edge blocks alone; the
  // widening reaches at most `cap` level pixels past M_ℓ, so its passes are drawn over the
  // blocks within `cap` of M_ℓ's (along x, then along y too), and the blur below over those.
  std::array<BlockMap, kLevelCount> maskBlocks;
  for (int l = 0; l < kLevelCount; ++l) maskBlocks[static_cast<size_t>(l)] = l == 0 ? fineBlocks : edgeBlocks;
  if (footprint) {
    Target pooled;
    // F, drawn over E's 4×4 blocks
    unsigned fl = footprint(Cover::blocksOf(fineBlocks, 1 << (kCoarsest - 1)));
    for (int l = 0; l < kLevelCount; ++l) {
      const LevelConstants& lc = level(l);
      const size_t i = static_cast<size_t>(l);
      if (l > 0) {
        Pass::Inputs in;
        in.source = fl;
        in.factor = 2;
        in.cover = Cover::whole();  // a coarser level (step 1)
        pooled = pass.run(1, {Texel::R32f}, lc.width, lc.height, in);
        fl = pooled->texture(0);
      }
      if (!lc.enabled || l == c.coarsestEnabled) continue;
      if (l < c.effectMask.firstLevel) {
        // SPEC §12.3, the effect-only arm: a level the effect does not widen holds nothing
        if (c.effectMask.effectOnly)
          mask[static_cast<size_t>(l)] = constantTarget(scene, lc.width, lc.height, Texel::R8, 0.0f);
        continue;
      }
      const unsigned source = l == 0 ? edges : mask[i]->texture(0);
      const int channel = l == 0 ? edgeChannel : 0;
      const BlockMap across = levelMap(l, lm[i].acrossCap), within = levelMap(l, lm[i].within);
      Target dilated = drawDilateByReach(scene, source, channel, fl, lc.width, lc.height, lc.scale, cap,
                                         cover(across, l), cover(within, l));
      if (c.effectMask.effectOnly)  // SPEC §12.3: M'_ℓ ∧ ¬M_ℓ
        dilated = drawWideningOnly(scene, dilated->texture(0), source, channel, lc.width, lc.height, cover(within, l));
      mask[i] = std::move(dilated);
      maskBlocks[i] = within;
      out->widenedBy[i] = cap;
    }
  }
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const size_t i = static_cast<size_t>(l);
    if (l == c.coarsestEnabled) {  // 2. the coarsest enabled level covers everything
      out->alphaTarget[i] = constantTarget(scene, lc.width, lc.height, Texel::R32f, 1.0f);
      stencil[i] = constantTarget(scene, lc.width, lc.height, Texel::R8, 1.0f);
      continue;
    }
    // 2. a_ℓ = G(σ²) ∗ M_ℓ, separable, over the blocks within r_ℓ of M_ℓ's (an edge's, or a
    // widened level's reach); 3. S_ℓ = [a_ℓ > 0]. The horizontal pass is non-zero only within r
    // across of M_ℓ's blocks (its rows); the vertical one within r across and down.
    out->supportBlocks[i] = mapOf(coarseMaps, lm[i].support);
    out->maskBlocks[i] = l != 0 ? maskBlocks[i] : lm[0].widened ? mapOf(coarseMaps, pooledWithin0) : edgeBlocks;
    Pass::Inputs horizontal;
    horizontal.source = mask[i] ? mask[i]->texture(0) : edges;  // M_0 = E unless mrr-effect replaced it
    horizontal.sourceChannel = mask[i] ? 0 : edgeChannel;
    if (limit) {  // 5. SPEC §13: M'_ℓ = M_ℓ where ℓ ≥ ℓ_min (0 outside M_ℓ's blocks, as M_ℓ); the blur reads it
      Pass::Inputs limited = horizontal;
      limited.factor = lc.scale;
      limited.limit = limit;
      limited.level = l;
      limited.cover = cover(maskBlocks[i], l);
      out->limitedTarget[i] = pass.run(5, {Texel::R8}, lc.width, lc.height, limited);
      horizontal.source = out->limitedTarget[i]->texture(0);
      horizontal.sourceChannel = 0;
    }
    out->blurSource[i] = horizontal.source;
    out->blurSourceChannel[i] = horizontal.sourceChannel;
    horizontal.weights = &lc.gaussian;
    horizontal.cover = cover(levelMap(l, lm[i].across), l);
    const Target h = pass.run(2, {Texel::R32f}, lc.width, lc.height, horizontal);
    Pass::Inputs vertical = horizontal;
    vertical.cover = cover(levelMap(l, lm[i].near), l);
    vertical.source = h->texture(0);
    vertical.sourceChannel = 0;
    vertical.direction = {0, 1};
    vertical.withStencil = true;
    Target both = pass.run(2, {Texel::R32f, Texel::R8}, lc.width, lc.height, vertical);
    out->alphaTarget[i] = std::move(both);  // a_ℓ in target 0, S_ℓ in target 1
  }
  // 4. coverage closure, fine to coarse, across disabled levels: S_next ∨ max-pool(S_ℓ) is 0
  // outside both supports, drawn over their union (S_next's, which holds every finer level's)
  auto stencilTexture = [&](size_t l) {
    return stencil[l] ? stencil[l]->texture(0) : out->alphaTarget[l]->texture(1);
  };
  for (int l = 0; l < kLevelCount; ++l) {
    const int next = c.nextCoarserEnabled(l);
    if (!c.levels[static_cast<size_t>(l)].enabled || next < 0) continue;
    const LevelConstants& ln = c.levels[static_cast<size_t>(next)];
    if (next == c.coarsestEnabled) continue;  // already all 1
    Pass::Inputs in;
    in.source = stencilTexture(static_cast<size_t>(l));
    in.previous = stencilTexture(static_cast<size_t>(next));
    in.factor = 1 << (next - l);
    in.cover = Cover::whole();  // S_next is a coarser level's (step 1)
    stencil[static_cast<size_t>(next)] = pass.run(4, {Texel::R8}, ln.width, ln.height, in);
  }
  for (Target& t : fineMaps) out->blockMaps.push_back(std::move(t));
  for (Target& t : coarseMaps) out->blockMaps.push_back(std::move(t));
  for (size_t l = 0; l < kLevelCount; ++l)
    if (c.levels[l].enabled) {
      out->alpha[l] = out->alphaTarget[l]->texture(0);
      out->stencil[l] = stencilTexture(l);
    }
  // 5. mrr-effect's trim (SPEC §12.5): each level ℓ ≥ 1 only where the blend reads it
  if (footprint && c.effectMask.trim) trimToBlend(scene, *out, c);
  return out;
}

void trimToBlend(const GpuScene& scene, MaskTargets& masks, const Constants& c) {
  // 1. R(p) from the a-priori S and a (blend.frag REACH)
  std::array<LevelTextures, kLevelCount> levels;
  for (size_t l = 0; l < kLevelCount; ++l) levels[l] = {0, masks.stencil[l], masks.alpha[l]};
  const Target reach = blendReach(scene, levels, c, masks.blendNear);  // far from every edge: C
  const int margin = trimMargin(c);
  // trim.frag STEP `step` for level ℓ into a fresh R8 target of width × height
  const auto step = [&](int n, int l, unsigned source, int width, int height, unsigned read = 0) {
    const unsigned program = scene.program("trim." + std::to_string(n) + "." + std::to_string(l) + "." + std::to_string(margin),
                                           "fullscreen.vert", "trim.frag",
                                           "#define STEP " + std::to_string(n) + "\n#define LEVEL " + std::to_string(l) +
                                               "\n#define MARGIN " + std::to_string(margin) + "\n");
    Target target = scene.target(width, height, {Texel::R8}, false);
    target->bind();
    glUseProgram(program);
    bindTextures(program, {{"source", source}});
    if (read) bindTextures(program, {{"read", read}}, 1);
    if (n <= 2) glUniform2i(uniform(program, "frame"), c.width, c.height);
    scene.drawFullscreen();
    checkGl("trim");
    return target;
  };
  for (int l = 1; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const size_t i = static_cast<size_t>(l);
    // 2. D_ℓ: the taps of the pixels with R ≥ ℓ (2a, 2b), within SSAO's blur radius (2c)
    const Target across = step(1, l, reach->texture(0), lc.width, c.levels[0].height);
    Target read = step(2, l, across->texture(0), lc.width, lc.height);
    if (margin > 0) {
      const Target wide = step(3, l, read->texture(0), lc.width, lc.height);
      read = step(4, l, wide->texture(0), lc.width, lc.height);
    }
    // 3. S_ℓ ∧= D_ℓ
    masks.stencilTarget[i] = step(5, l, masks.stencil[i], lc.width, lc.height, read->texture(0));
    masks.readTarget[i] = std::move(read);
    masks.stencil[i] = masks.stencilTarget[i]->texture(0);
  }
}

Target drawLevelLimited(const GpuScene& scene, unsigned mask, int level, unsigned limit, const Constants& c) {
  const LevelConstants& lc = c.levels[static_cast<size_t>(level)];
  Pass::Inputs in;
  in.source = mask;
  in.factor = lc.scale;
  in.limit = limit;
  in.level = level;
  return Pass{scene}.run(5, {Texel::R8}, lc.width, lc.height, in);
}

void refineMasks(const GpuScene& scene, MaskTargets& masks, int level, Target marks, const Constants& c,
                 const BlockMap& marksIn) {
  BlockMap marksBlocks = marksIn;
  const size_t i = static_cast<size_t>(level);
  const LevelConstants& lc = c.levels[i];
  require(masks.drawn && masks.blurSource[i] != 0, "refineMasks: level " + std::to_string(level) + " has no drawn blur");
  // With the marks' blocks, each step is drawn over the blocks where it can be non-zero (the
  // rest cleared to 0, what the step gives there), as drawMasks' passes: level-ℓ pixels per block
  const int blockSize = 1 << (kLevelCount - 1 - level);
  if (marksBlocks && (!masks.maskBlocks[i] || !masks.supportBlocks[i] ||
                      marksBlocks.width() != masks.maskBlocks[i].width() ||
                      marksBlocks.height() != masks.maskBlocks[i].height()))
    marksBlocks = BlockMap();  // blocks on another grid: the whole level
  const auto coverOf = [&](const BlockMap& blocks) { return Cover::blocksOf(blocks, blockSize); };
  const unsigned read = masks.readTarget[i] ? masks.readTarget[i]->texture(0) : 0;  // D_ℓ (SPEC §12.5), or none
  // The step's program: refine_masks.frag STEP 1 or 3 (SOURCE_CHANNEL: M_ℓ's channel, step 1).
  const auto step = [&](int n, int channel, std::initializer_list<std::pair<const char*, unsigned>> textures,
                        const Cover& cover) {
    const bool withRead = textures.size() == 3;  // step 3 of a trimmed level: S_ℓ's D_ℓ too
    const unsigned program =
        scene.passProgram("refine_masks." + std::to_string(n) + "." + std::to_string(channel) + (withRead ? ".read" : ""),
                          "refine_masks.frag",
                          "#define STEP " + std::to_string(n) + "\n#define SOURCE_CHANNEL " + std::to_string(channel) +
                              "\n" + (withRead ? "#define WITH_READ\n" : ""),
                          cover);
    Target target = scene.target(lc.width, lc.height, 1, false, Texel::R8);
    target->bind();
    glUseProgram(program);
    bindTextures(program, textures);
    if (!cover.isWhole()) {
      const float zero[4] = {0, 0, 0, 0};
      glClearBufferfv(GL_COLOR, 0, zero);
    }
    scene.draw(cover, lc.width, lc.height);
    checkGl("refine_masks");
    return target;
  };
  // 1. M_ℓ ∨= marks: 0 outside M_ℓ's blocks and the marks'
  const BlockMap refined = marksBlocks ? masks.keep(uniteBlocks(scene, masks.maskBlocks[i], marksBlocks)) : BlockMap();
  masks.refinedTarget[i] = step(1, masks.blurSourceChannel[i], {{"source", masks.blurSource[i]}, {"marks", marks->texture(0)}},
                                refined ? coverOf(refined) : Cover::whole());
  masks.marksTarget[i] = std::move(marks);
  const Pass pass{scene};
  Pass::Inputs horizontal;
  horizontal.source = masks.refinedTarget[i]->texture(0);
  horizontal.weights = &lc.gaussian;
  Pass::Inputs vertical = horizontal;
  vertical.direction = {0, 1};
  if (!marksBlocks) {
    // 2. a_ℓ = G(σ_ℓ²) ∗ M_ℓ again: masks.frag's two passes, over the whole level
    const Target h = pass.run(2, {Texel::R32f}, lc.width, lc.height, horizontal);
    vertical.source = h->texture(0);
    Target alpha = pass.run(2, {Texel::R32f}, lc.width, lc.height, vertical);
    // 3. S_ℓ ∨= [a_ℓ > 0], ∧ D_ℓ where trimmed (SPEC §12.5)
    Target stencil = read ? step(3, 0, {{"source", masks.stencil[i]}, {"alpha", alpha->texture(0)}, {"read", read}}, Cover::whole())
                          : step(3, 0, {{"source", masks.stencil[i]}, {"alpha", alpha->texture(0)}}, Cover::whole());
    masks.alphaTarget[i] = std::move(alpha);
    masks.stencilTarget[i] = std::move(stencil);
    masks.supportBlocks[i] = BlockMap();  // the whole level
  } else {
    // 2. a_ℓ = G(σ_ℓ²) ∗ M_ℓ again. M_ℓ changed in the marks' blocks alone, so a_ℓ changes within
    // r_ℓ of them alone (each pixel's sum is the blur's own, term for term): a copy of a_ℓ, the
    // vertical pass redrawn there, the horizontal one where that reads it (r_ℓ further down).
    // Without a mark the covers are empty: a_ℓ and S_ℓ are copied as they were.
    const int radius = blocksWithin(static_cast<int>(lc.gaussian.size() / 2), blockSize);
    const BlockMap changed = masks.keep(dilateBlocks(scene, marksBlocks, radius, radius));
    const BlockMap rows = masks.keep(dilateBlocks(scene, changed, 0, radius));
    horizontal.cover = coverOf(rows);
    const Target h = pass.run(2, {Texel::R32f}, lc.width, lc.height, horizontal);
    Target alpha = scene.target(lc.width, lc.height, 1, false, Texel::R32f);
    alpha->copyFrom(*masks.alphaTarget[i], 0);
    vertical.source = h->texture(0);
    vertical.cover = coverOf(changed);
    pass.draw(2, *alpha, vertical, false);
    // 3. S_ℓ ∨= [a_ℓ > 0]: likewise, a copy of S_ℓ redrawn where a_ℓ changed
    const Cover changedCover = coverOf(changed);
    const unsigned program = scene.passProgram(std::string("refine_masks.3.0") + (read ? ".read" : ""), "refine_masks.frag",
                                               std::string("#define STEP 3\n#define SOURCE_CHANNEL 0\n") +
                                                   (read ? "#define WITH_READ\n" : ""),
                                               changedCover);
    Target stencil = scene.target(lc.width, lc.height, 1, false, Texel::R8);
    if (masks.stencilTarget[i]) stencil->copyFrom(*masks.stencilTarget[i], 0);
    else stencil->copyFrom(*masks.alphaTarget[i], 1);  // S_ℓ beside a_ℓ (the blur's second target)
    glUseProgram(program);
    bindTextures(program, {{"source", masks.stencil[i]}, {"alpha", alpha->texture(0)}});
    if (read) bindTextures(program, {{"read", read}}, 2);
    scene.draw(changedCover, lc.width, lc.height);
    checkGl("refine_masks");
    masks.alphaTarget[i] = std::move(alpha);
    masks.stencilTarget[i] = std::move(stencil);
    masks.maskBlocks[i] = refined;
    masks.supportBlocks[i] = masks.keep(uniteBlocks(scene, masks.supportBlocks[i], changed));
  }
  masks.alpha[i] = masks.alphaTarget[i]->texture(0);
  masks.stencil[i] = masks.stencilTarget[i]->texture(0);
}

Target drawLevelLimit(const GpuScene& scene, const Framebuffer& gbuffer0, const View& view, const Constants& c) {
  const Constants::Foveation& f = c.foveation;
  const unsigned program = scene.program("limit", "fullscreen.vert", "limit.frag", "");
  Target target = scene.target(c.paddedWidth, c.paddedHeight, 1, false, Texel::Rgba32f);
  target->bind();
  glUseProgram(program);
  bindTextures(program, {{"positionHit", gbuffer0.texture(0)}});
  glUniform1i(uniform(program, "gaze"), f.gaze ? 1 : 0);
  glUniform1i(uniform(program, "foveate"), f.foveate ? 1 : 0);
  glUniform1i(uniform(program, "motion"), f.motion ? 1 : 0);
  glUniform2i(uniform(program, "gazePixel"), f.gazeX, f.gazeY);
  glUniform1f(uniform(program, "ppd"), f.ppd);
  int radius2[kLevelCount];
  for (size_t l = 0; l < kLevelCount; ++l)  // d² < 2³¹ on any allowed grid: a larger radius is never reached
    radius2[l] = static_cast<int>(std::min<int64_t>(f.radius2[l], int64_t{0x7fffffff}));
  glUniform1iv(uniform(program, "radius2"), kLevelCount, radius2);
  glUniform1fv(uniform(program, "speed2"), kLevelCount, f.speed2.data());
  glUniform1i(uniform(program, "motionCap"), f.motionCap);
  glUniform1i(uniform(program, "coarsest"), c.coarsestEnabled);
  glUniform1f(uniform(program, "motionScale"), f.motionScale);
  const auto vec3 = [&](const char* name, const glm::vec3& v) { glUniform3f(uniform(program, name), v.x, v.y, v.z); };
  vec3("viewEye", view.eye);
  vec3("viewRight", view.right);
  vec3("viewUp", view.up);
  vec3("viewForward", view.forward);
  const View prev = f.motion ? previousView(c, view) : view;
  vec3("prevEye", prev.eye);
  vec3("prevRight", prev.right);
  vec3("prevUp", prev.up);
  vec3("prevForward", prev.forward);
  glUniform1f(uniform(program, "prevFocal"), prev.focal);
  glUniform1f(uniform(program, "prevCx"), prev.cx);
  glUniform1f(uniform(program, "prevCy"), prev.cy);
  scene.drawFullscreen();
  checkGl("limit");
  return target;
}

void readLevelLimit(const Framebuffer& target, const Constants& c, ImageF& eccentricity, ImageF& motion, ImageU8& limit) {
  const ImageF all = target.read(0);
  const int w = all.width, h = all.height;
  eccentricity = c.foveation.gaze ? ImageF::uninitialised(w, h) : ImageF();
  motion = c.foveation.motion ? ImageF::uninitialised(w, h) : ImageF();
  limit = ImageU8(w, h, kLimitChannels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (c.foveation.gaze) eccentricity.at(x, y) = all.at(x, y, 0);
      if (c.foveation.motion) motion.at(x, y) = all.at(x, y, 1);
      const int packed = static_cast<int>(all.at(x, y, 2));
      limit.at(x, y, kLimitFovea) = static_cast<uint8_t>(packed % 4);
      limit.at(x, y, kLimitMotion) = static_cast<uint8_t>(packed / 4);
      limit.at(x, y, kLimitLevel) = static_cast<uint8_t>(all.at(x, y, 3));
    }
}

std::array<MaskLevel, kLevelCount> readMasks(const MaskTargets& masks, const Constants& c, bool stencilsOnly) {
  std::array<MaskLevel, kLevelCount> out;
  for (size_t l = 0; l < kLevelCount; ++l) {
    if (!stencilsOnly && masks.refinedTarget[l]) out[l].mask = masks.refinedTarget[l]->readBinary(0);  // SPEC §12.2
    else if (!stencilsOnly && masks.limitedTarget[l]) out[l].mask = masks.limitedTarget[l]->readBinary(0);  // SPEC §13
    else if (!stencilsOnly && masks.maskTarget[l]) out[l].mask = masks.maskTarget[l]->readBinary(0);  // ℓ ≥ 1
    if (!c.levels[l].enabled) continue;
    out[l].stencil = masks.stencilTarget[l] ? masks.stencilTarget[l]->readBinary(0)
                                            : masks.alphaTarget[l]->readBinary(1);
    if (!stencilsOnly) out[l].alpha = masks.alphaTarget[l]->read(0, 1);
    if (!stencilsOnly && masks.readTarget[l]) out[l].read = masks.readTarget[l]->readBinary(0);  // SPEC §12.5
  }
  return out;
}

std::unique_ptr<MaskTargets> uploadMasks(const std::array<MaskLevel, kLevelCount>& masks, const Constants& c) {
  auto out = std::make_unique<MaskTargets>();
  for (size_t l = 0; l < kLevelCount; ++l) {
    if (!c.levels[l].enabled) continue;
    out->stencil[l] = out->uploaded.add(uploadBinary(masks[l].stencil));
    out->alpha[l] = out->uploaded.add(uploadTexture(masks[l].alpha));
  }
  return out;
}

namespace {
// A target of `format`, 0 but on [0, w) × [0, h), where it is `value` (a scissored clear).
Target insideTarget(const GpuScene& scene, int width, int height, Texel format, int w, int h, float inside,
                    float outside = 0.0f) {
  Target target = scene.target(width, height, 1, false, format);
  target->bind();
  const float out[4] = {outside, outside, outside, outside}, in[4] = {inside, inside, inside, inside};
  glClearBufferfv(GL_COLOR, 0, out);
  glEnable(GL_SCISSOR_TEST);
  glScissor(0, 0, w, h);
  glClearBufferfv(GL_COLOR, 0, in);
  glDisable(GL_SCISSOR_TEST);
  checkGl("constant masks");
  return target;
}
}  // namespace

std::unique_ptr<MaskTargets> drawFullMasks(const GpuScene& scene, const Constants& c) {
  // as fullModeMasks: S_0 on the W×H pixels, a_0 = 1 on the whole padded level
  auto out = std::make_unique<MaskTargets>();
  const LevelConstants& l0 = c.levels[0];
  out->stencilTarget[0] = insideTarget(scene, l0.width, l0.height, Texel::R8, c.width, c.height, 1.0f);
  out->alphaTarget[0] = insideTarget(scene, l0.width, l0.height, Texel::R32f, l0.width, l0.height, 1.0f);
  out->stencil[0] = out->stencilTarget[0]->texture(0);
  out->alpha[0] = out->alphaTarget[0]->texture(0);
  return out;
}

std::unique_ptr<MaskTargets> drawUniformMasks(const GpuScene& scene, const Constants& c) {
  // as uniformMasks: S_ℓ = a_ℓ = 1 on the level pixels whose block starts inside W×H, at the
  // shaded levels; 0 at an unshaded one (uniform-k's level 0)
  auto out = std::make_unique<MaskTargets>();
  for (size_t l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[l];
    if (!lc.enabled) continue;
    const int w = lc.shaded ? levelExtent(c.width, lc.scale) : 0, h = lc.shaded ? levelExtent(c.height, lc.scale) : 0;
    out->stencilTarget[l] = insideTarget(scene, lc.width, lc.height, Texel::R8, w, h, 1.0f);
    out->alphaTarget[l] = insideTarget(scene, lc.width, lc.height, Texel::R32f, w, h, 1.0f);
    out->stencil[l] = out->stencilTarget[l]->texture(0);
    out->alpha[l] = out->alphaTarget[l]->texture(0);
  }
  return out;
}

std::array<MaskLevel, kLevelCount> buildMasks(const GpuScene& scene, const ImageU8& edges, const Constants& c,
                                              const ImageF* footprint) {
  TextureSet uploaded;
  FootprintFn f;
  if (footprint) f = [&](const Cover&) { return uploaded.add(uploadTexture(*footprint)); };
  const auto targets = drawMasks(scene, uploaded.add(uploadBinary(edges)), 0, c, f);
  std::array<MaskLevel, kLevelCount> masks = readMasks(*targets, c, false);
  if (masks[0].mask.empty()) masks[0].mask = edges;  // M_0 = E (mrr-effect may have widened it)
  return masks;
}

}  // namespace mrr::gpu
