#pragma once
// Stage 3 — mask pyramid, blur and stencils (SPEC §3).
#include <array>

#include "common/image.h"
#include "common/params.h"

namespace mrr {

struct MaskLevel {
  ImageU8 mask;     // M_ℓ: 2×2 max-pool chain of E
  ImageF alpha;     // a_ℓ = G(σ_ℓ²) ∗ M_ℓ (≡ 1 at the coarsest enabled level); empty if disabled
  ImageU8 stencil;  // S_ℓ = [a_ℓ > 0], closed from fine to coarse; empty if disabled
};

// factor×factor max-pool (an edge anywhere in the block marks the block).
ImageU8 maxPool(const ImageU8& src, int factor);

// Separable Gaussian with the given normalised weights, clamp-to-edge (SPEC §3).
ImageF blurMask(const ImageU8& mask, const std::vector<float>& weights);

// The whole of SPEC §3 for multires mode. `edges` is E on the padded full-res grid.
std::array<MaskLevel, kLevelCount> buildMasks(const ImageU8& edges, const Constants& constants);

// Mode `full`: level 0 shades exactly the W×H pixels; nothing else is built.
std::array<MaskLevel, kLevelCount> fullModeMasks(const Constants& constants);

}  // namespace mrr
