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

// The whole of SPEC §3 for multires mode. `edges` is E on the padded full-res grid.
// mrr-effect (SPEC §12): `footprint` (cpu_ref/effect_masks.h) widens each enabled level's M_ℓ
// but the coarsest before its blur; null: the paper's masks, untouched.
// Foveation and motion (SPEC §13): `levelLimit` (cpu_ref/foveation.h) clears M_ℓ where ℓ < ℓ_min,
// after the pyramid and the widening, before the blur; null: no limit.
std::array<MaskLevel, kLevelCount> buildMasks(const ImageU8& edges, const Constants& constants,
                                              const ImageF* footprint = nullptr, const ImageU8* levelLimit = nullptr);

}  // namespace mrr
