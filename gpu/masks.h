#pragma once
// The port's stage 3 (gpu/shaders/masks.frag): mask pyramid, blur, stencils and the coverage
// closure on the GPU. The targets stay there for the effect and blend passes; where they can be
// non-zero is known on the GPU alone (block maps, gpu/blocks.h). The frame counts S_ℓ there
// (gpu/rule.h) and reads the masks back only when it keeps its stages.
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Every enabled level's M_ℓ, a_ℓ and S_ℓ on the GPU: the port's masks behind the frame contract
// (common/frame.h DeviceMasks). The later passes read `alpha[ℓ]` and `stencil[ℓ]` (texture names;
// 0 for disabled levels), drawn here or by the host-free builders of full, uniform-k and tiles.
struct MaskTargets final : DeviceMasks {
  // Drawn: M_ℓ (R8, ℓ ≥ 1; M_0 is E); a_ℓ (R32F) with S_ℓ (R8) as its second target, or S_ℓ in
  // stencilTarget where the closure or the coarsest level made it.
  std::array<Target, kLevelCount> maskTarget, alphaTarget, stencilTarget;
  // SPEC §13: M'_ℓ, M_ℓ after the level limit (R8), for the levels it drew; the blur reads these
  // and readMasks reports them as M_ℓ (M'_0 too, where M_0 is otherwise E).
  std::array<Target, kLevelCount> limitedTarget;
  // Drawn: the M_ℓ each level's blur read (texture, channel): E for an unwidened level 0, M'_ℓ
  // after the limit, ... (0: the coarsest or a disabled level). SPEC §12.2 refines it.
  std::array<unsigned, kLevelCount> blurSource{};
  std::array<int, kLevelCount> blurSourceChannel{};
  // SPEC §12.2 (refineMasks): M_ℓ ∨ the marks (R8) and the marks themselves, for the levels
  // refined; readMasks reports the former as M_ℓ.
  std::array<Target, kLevelCount> refinedTarget, marksTarget;
  // SPEC §12.5 (trimToBlend): D_ℓ (R8), the level pixels the blend reads, for the levels trimmed;
  // S_ℓ ∧= D_ℓ is in stencilTarget[ℓ], and refineMasks keeps it.
  std::array<Target, kLevelCount> readTarget;
  TextureSet uploaded;                                                       // or uploaded
  std::array<unsigned, kLevelCount> alpha{}, stencil{};
  bool drawn = false;  // the edge pyramid's (drawMasks): the fast paths below know where work is
  // Drawn: block maps on the coarsest level's grid (gpu/blocks.h; blocks of 2^{3−ℓ} level-ℓ
  // pixels, 8×8 full-res pixels): the blocks outside which the M_ℓ the blur read is 0 (E's edge
  // blocks, or a widened level's reach past them), and those outside which S_ℓ is 0 (none: the
  // whole level, the coarsest); refineMasks extends both. The effect passes' stencil fill is drawn
  // over supportCover(ℓ).
  std::array<BlockMap, kLevelCount> maskBlocks{}, supportBlocks{};
  BlockMap edgeBlocks;  // drawn: M of the coarsest level (which blocks hold an edge)
  BlockMap blendNear;   // drawn: the blocks within a finer level's reach of an edge block (the blend's)
  std::vector<Target> blockMaps;  // the block maps above, owned
  // Drawn, mrr-effect (SPEC §12): the most level pixels each level's M'_ℓ reaches past M_ℓ (its
  // cap where widened, else 0), for the blend's reach from the edge blocks.
  std::array<int, kLevelCount> widenedBy{};
  // Tiles (gpu/peers.h): each 16×16 tile's rate (R32F, tile grid), after SPEC §13's limit.
  Target tileRates;

  // Where to draw level ℓ's passes that have work only where S_ℓ can be set: supportBlocks[0]'s
  // runs at level 0; the whole level at a coarser one, where a cover costs more than the pixels
  // it skips (gpu/masks.cpp drawMasks, step 1), and wherever supportBlocks[ℓ] is none.
  Cover supportCover(int level) const;
  // Keeps a block map target and returns its first map.
  BlockMap keep(Target map);
};

// mrr-effect (SPEC §12): F on the padded full-res grid (R32F, gpu/effect_masks.h drawFootprint),
// drawn at least over `edgeRects` (rectangles holding every pixel of E, F's support; 0 elsewhere
// is what F is there; E's 4×4 blocks): its texture.
using FootprintFn = std::function<unsigned(const Cover& edgeBlocks)>;

// Stages 3.1–3.4 from E, channel `edgeChannel` of the texture `edges` (the padded full-res grid).
// mrr-effect (SPEC §12): `footprint` gives F, which widens M_ℓ before the blur; none: the paper's
// masks. `limit`: limit.frag's target texture (drawLevelLimit), or 0 without SPEC §13's terms.
std::unique_ptr<MaskTargets> drawMasks(const GpuScene& scene, unsigned edges, int edgeChannel,
                                       const Constants& constants, const FootprintFn& footprint = {},
                                       unsigned limit = 0);

// SPEC §12.5, mrr-effect's trim (gpu/shaders/trim.frag, cpu_ref/masks.cpp trimToBlend): R(p)
// from the drawn masks' S and a (blend.frag REACH), then for each enabled level ℓ ≥ 1 D_ℓ into
// readTarget[ℓ] and S_ℓ ∧= D_ℓ. drawMasks calls it last where the constants ask for it.
void trimToBlend(const GpuScene& scene, MaskTargets& masks, const Constants& constants);

// SPEC §13 steps 1–5 (limit.frag) on the padded full-res grid from the level-0 G-buffer:
// RGBA32F (e, |v|, fovea + 4·motion, ℓ_min).
Target drawLevelLimit(const GpuScene& scene, const Framebuffer& gbuffer0, const View& view, const Constants& constants);
// Its target read back as the frame's eccentricity (with a gaze), motion (with a previous frame)
// and level limit (kLimitChannels bytes).
void readLevelLimit(const Framebuffer& target, const Constants& constants, ImageF& eccentricity, ImageF& motion,
                    ImageU8& limit);

// SPEC §13 step 6 alone (masks.frag STEP 5): `mask` (R8, level ℓ's size) cleared where ℓ < ℓ_min
// at the full-res pixel each level pixel holds; `limit` is limit.frag's target texture.
Target drawLevelLimited(const GpuScene& scene, unsigned mask, int level, unsigned limit, const Constants& constants);

// SPEC §12.2 step 2, refineMasks (gpu/shaders/refine_masks.frag, its step 2 masks.frag's blur):
// level ℓ of drawn masks refined with `marks` (R8, level ℓ's size, already limited): M_ℓ ∨= marks
// (into refinedTarget[ℓ]), a_ℓ = G(σ_ℓ²) ∗ M_ℓ again and S_ℓ ∨= [a_ℓ > 0]; alpha[ℓ], stencil[ℓ] and
// their targets are replaced. Without `marksBlocks`, over the whole level (supportBlocks[ℓ]
// cleared: the whole level). With it (a block map of the coarsest level's grid, as
// MaskTargets::maskBlocks: 1 where a block may hold a mark, drawRefinementMarks' `blocks`), step 1
// is drawn over M_ℓ's blocks and the marks', and a_ℓ and S_ℓ change only within r_ℓ of the marks'
// blocks: copies of them, redrawn there; maskBlocks and supportBlocks of ℓ grow to the refined
// ones (no mark leaves a_ℓ and S_ℓ as they were). Both give the same bits. Not for the coarsest
// enabled level.
void refineMasks(const GpuScene& scene, MaskTargets& masks, int level, Target marks, const Constants& constants,
                 const BlockMap& marksBlocks = {});

// Reads drawn masks back: every S_ℓ, and M_ℓ (ℓ ≥ 1: M_0 is E, the caller's) and a_ℓ too
// unless `stencilsOnly`.
std::array<MaskLevel, kLevelCount> readMasks(const MaskTargets& masks, const Constants& constants, bool stencilsOnly);

// Passes that only have work near edges are drawn over blocks of the coarsest level's grid:
// `edgeBlocks` is M of the coarsest level (a block holds an edge), each block blockSize² pixels
// of the pass's level; nearBlocks (common/frame.h) dilates them to where the blur of M can be
// non-zero. blockRects: the row runs of the blocks set to `value` (1: near, 0: far) as pixel
// rectangles (x0, y0, x1, y1) clipped to width×height.
std::vector<glm::ivec4> blockRects(const ImageU8& blocks, uint8_t value, int blockSize, int width, int height);
// The blocks of blockSize² pixels of `mask` that hold a set pixel (the last row and column of
// blocks may be partial): the host's block map of a read-back mask.
ImageU8 blocksOf(const ImageU8& mask, int blockSize);

// Host masks as textures for the passes (a frame that hands the port host images).
std::unique_ptr<MaskTargets> uploadMasks(const std::array<MaskLevel, kLevelCount>& masks, const Constants& constants);
// full's and uniform-k's stencils (common/frame.h fullModeMasks, uniformMasks: constants of the
// frame's size), drawn on the GPU: S = a = 1 on the level pixels whose block starts inside W×H
// (full: level 0's W×H pixels, a_0 = 1 everywhere), 0 elsewhere; nothing is uploaded.
std::unique_ptr<MaskTargets> drawFullMasks(const GpuScene& scene, const Constants& constants);
std::unique_ptr<MaskTargets> drawUniformMasks(const GpuScene& scene, const Constants& constants);

// Draw from a host E (uploaded as a texture) and read everything back: the same-input form.
// mrr-effect: `footprint` is the host's F (null: the paper's masks).
std::array<MaskLevel, kLevelCount> buildMasks(const GpuScene& scene, const ImageU8& edges, const Constants& constants,
                                              const ImageF* footprint = nullptr);

}  // namespace mrr::gpu
