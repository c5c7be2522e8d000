#pragma once
// Stage 3 — mask pyramid, blur and stencils (SPEC §3).
#include <array>

#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"

namespace mrr {

// factor×factor max-pool (an edge anywhere in the block marks the block).
ImageU8 maxPool(const ImageU8& src, int factor);

// Separable Gaussian with the given normalised weights, clamp-to-edge (SPEC §3).
ImageF blurMask(const ImageU8& mask, const std::vector<float>& weights);

// blurMask again after `mask` changed only in the rows flagged in `changedRows` and the columns
// [changedX0, changedX1): the pixels of `alpha` such a change can reach (within r rows and r
// columns) are recomputed with blurMask's own per-pixel sums, the rest kept: the same bits as
// blurMask(mask) when `alpha` was blurMask of the mask before (SPEC §12.2's fast path).
void reblurMaskRegion(const ImageU8& mask, const std::vector<float>& weights, const std::vector<uint8_t>& changedRows,
                      int changedX0, int changedX1, ImageF& alpha);

// SPEC §3 step 1 and §12's widening, with what they are made of (SPEC §12.3, for `probe`'s and
// `explore`'s "why"): `geometry` is M_ℓ from E alone (the paper's pyramid, every level); with a
// footprint, `footprintMax` is F_ℓ (the footprint's 2×2 max-pool chain), `reach` K_ℓ at the
// widened levels (empty elsewhere) and `widened` the masks buildMasks blurs (M'_ℓ; the
// effect-only arm's M'_ℓ ∧ ¬M_ℓ), all empty without one (then M_ℓ = geometry). No level limit.
struct MaskStages {
  std::array<ImageU8, kLevelCount> geometry, widened;
  std::array<ImageF, kLevelCount> footprintMax;
  std::array<Image<int16_t>, kLevelCount> reach;
};
MaskStages maskStages(const ImageU8& edges, const Constants& constants, const ImageF* footprint);

// SPEC §3 steps 2–4 on a pyramid: `levels[ℓ].mask` holds M_ℓ for every enabled level; each
// enabled level gets a_ℓ = G(σ_ℓ²) ∗ M_ℓ (≡ 1 at the coarsest enabled level) and S_ℓ = [a_ℓ > 0],
// then the coverage closure, fine to coarse. buildMasks ends with it, and masks made elsewhere (a
// mask rule written in numpy, python/, docs/python.md) go through the same blur and closure.
void stencilsFromPyramid(Masks& levels, const Constants& constants);

// SPEC §12.5, mrr-effect's trim: shade a level only where the blend reads it.
// D_ℓ = the level pixels within `margin` (common/params.h trimMargin: SSAO's blur radius, 0 for SSM and SSGI) of a
// bilinear tap (SPEC §5) of some full-res pixel p of W×H with R(p) ≥ ℓ (`reach`, blendReach):
// the taps' floor(u) is q − 1 or q, so p ∈ [q s − s/2, q s + 3s/2) per axis. blendReadsReference
// is the rule pixel by pixel; blendReads the same separably (along x, then y, then the margin),
// tested equal.
ImageU8 blendReadsReference(const ImageU8& reach, int level, int margin, const Constants& constants);
ImageU8 blendReads(const ImageU8& reach, int level, int margin, const Constants& constants);
// Steps 1–3 on masks after the closure: R from their S and a, then for each enabled level ℓ ≥ 1
// D_ℓ into `read` and S_ℓ ∧= D_ℓ. A full-res pixel with R(p) ≥ ℓ keeps all four of its taps, so
// the final image is the untrimmed one's bit for bit (without the a-posteriori term, which reads
// the trimmed results).
void trimToBlend(Masks& levels, const Constants& constants);
// Step 3, S_ℓ ∧= D_ℓ, where `level.read` holds D_ℓ (nothing where it is empty); §12.2's
// refinement ends with it too.
void keepBlendReads(MaskLevel& level);

// The whole of SPEC §3 for multires mode. `edges` is E on the padded full-res grid.
// mrr-effect (SPEC §12): `footprint` (cpu_ref/effect_masks.h) widens each enabled level's M_ℓ
// but the coarsest before its blur; null: the paper's masks, untouched.
// Foveation and motion (SPEC §13): `levelLimit` (cpu_ref/foveation.h) clears M_ℓ where ℓ < ℓ_min,
// after the pyramid and the widening, before the blur; null: no limit.
std::array<MaskLevel, kLevelCount> buildMasks(const ImageU8& edges, const Constants& constants,
                                              const ImageF* footprint = nullptr, const ImageU8* levelLimit = nullptr);

}  // namespace mrr
