#pragma once
// The port's mrr-effect masks (SPEC §12; gpu/shaders/effect_masks.frag), mirroring
// cpu_ref/effect_masks.h function by function: the footprint at full res, then each level's
// reach and its two-pass dilation. gpu/masks.cpp calls the dilation between the pyramid and
// the blur. The a-posteriori term (SPEC §12.2): the marks here, the refinement in gpu/masks.h
// (refineMasks, which reuses masks.frag's blur).
#include <vector>

#include "common/camera.h"
#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Step 1, effectFootprint: F on the padded full-res grid (R32F), from level 0's G-buffer and
// E (channel `edgeChannel` of `edges`). SSM reads the light's map (`map`, `mapTexture`); the
// others pass 0. Over `cover` alone (where it holds every pixel of E): F is 0 elsewhere.
Target drawFootprint(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned edges, int edgeChannel,
                     const ShadowMap* map, unsigned mapTexture, const View& view, const Constants& constants,
                     const Cover& cover = {});

// Steps 2–3, levelReach and dilateByReach: M'_ℓ (R8) from M_ℓ (channel `maskChannel` of `mask`)
// and F_ℓ (`footprint`, R32F at level ℓ's size), widened by at most `cap` level pixels. The pass
// along x is drawn over `across` (holding every pixel within `cap` along x of M_ℓ; elsewhere
// H = −1) and the pass along y over `within` (every pixel within `cap` across and down; elsewhere
// M'_ℓ = 0): what the whole level gives.
Target drawDilateByReach(const GpuScene& scene, unsigned mask, int maskChannel, unsigned footprint, int width,
                         int height, int levelScale, int cap, const Cover& across = {}, const Cover& within = {});

// SPEC §12.3, wideningOnly (the ablation's effect-only arm, effect_masks.frag STEP 4): M'_ℓ ∧ ¬M_ℓ
// (R8) from `widened` (drawDilateByReach's M'_ℓ) and M_ℓ (channel `maskChannel` of `mask`), over
// `within` alone (elsewhere 0), as drawDilateByReach.
Target drawWideningOnly(const GpuScene& scene, unsigned widened, unsigned mask, int maskChannel, int width, int height,
                        const Cover& within = {});

// SPEC §12.2 step 1, refinementMarks (gpu/shaders/refinement_marks.frag): the a-posteriori marks
// (R8, finerWidth × finerHeight) of a finer level from its next coarser enabled level's result
// `coarser` (its first `channels` channels; SSAO: after the bilateral blur), stencil and
// G-buffer (`coarserPositionHit`, hit in w); `ratio` = 2^{n−ℓ}, `tau` = τ_v. The level limit
// (SPEC §13) is the caller's: masks.h drawLevelLimited. Step 1 is drawn over `shaded` alone (it
// holds every pixel of S_n: MaskTargets::supportCover), and with `blocks` its marks are pooled on
// the GPU into a block map of blocks of `blockSize` coarser pixels (1: the block holds a mark;
// gpu/blocks.h), step 2 then drawn over those blocks alone; elsewhere both give 0, as over the
// whole level.
Target drawRefinementMarks(const GpuScene& scene, unsigned coarser, int channels, unsigned coarserStencil,
                           unsigned coarserPositionHit, int ratio, int finerWidth, int finerHeight, float tau,
                           const Cover& shaded = {}, Target* blocks = nullptr, int blockSize = 1);

// Its two steps apart. Step 1 at level n: [v(q) > τ] (R8), or with `rangeOut` v(q) itself (R32F,
// −1 where q is not a shaded hit pixel: SPEC §12.4's budget selects on the host), drawn over
// `shaded` as above; by the separable passes along x then y (localRangesSeparable), or with
// `whole` the readable single pass over each 3×3 (localRange): the same bits.
Target drawRangeTest(const GpuScene& scene, unsigned coarser, int channels, unsigned coarserStencil,
                     unsigned coarserPositionHit, float tau, const Cover& shaded, bool rangeOut, bool whole = false);
// Step 2 at level ℓ from level n's marks `varies` (R8), as drawRefinementMarks: with `blocks`,
// they are pooled into blocks of `blockSize` level-n pixels and the pass drawn over those alone.
Target drawParentMarks(const GpuScene& scene, Target varies, int ratio, int finerWidth, int finerHeight,
                       Target* blocks = nullptr, int blockSize = 1);

// SPEC §12.4's budgeted selection on the GPU (refinement_budget.frag), common/effect_budget.h's
// steps: each level-n pixel's price from the a-priori S_ℓ (`finerStencil`), level 0's hit
// (`positionHit0`, in w) and SSM's PCF sample (`pcfSample`, 0 without); its key from v (`range`,
// drawRangeTest's RANGE_OUT); the threshold found kBudgetRadix keys a pass from the level's share
// of what is left (the frame's budget `r.leftUnits`, or what `before`, the refined level before
// this one, left); the marks. Nothing is read back: the state stays on the GPU for the next level
// and for the report's figures after the clock.
struct BudgetedSelection {
  Target candidates;  // level n, RGBA32UI: (price, key or kBudgetKeys, marked before, 0)
  Target state;       // 1×1, RGBA32UI: (T, left, S(T), share)
  Target marks;       // level n, R8: [key ≥ T]
};
BudgetedSelection drawBudgetedSelection(const GpuScene& scene, unsigned range, unsigned finerStencil,
                                        unsigned positionHit0, unsigned pcfSample, const Constants& constants, int level,
                                        int coarser, const RefinementRecord& r, const Framebuffer* before);
// Step 9, after the clock: per level-n pixel (candidate, marked, marked and marked before, 0)
// (RGBA32UI), for gpu/counts.h to sum.
Target drawBudgetCounts(const GpuScene& scene, const BudgetedSelection& selection);

}  // namespace mrr::gpu
