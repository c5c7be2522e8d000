#pragma once
// The peers the method is charted against (SPEC §9): which pixels each one shades (its
// stage 3) and how its levels become the full-res image (its stage 5). They run the same
// G-buffers and the same effect code as the method; only the sampling strategy differs.
//   uniform-k  every pixel of level k, then joint bilateral upsampling (what games ship)
//   tiles      16×16 full-res tiles shaded at 1×1, 2×2 or 4×4 by their edges, broadcast
//              unfiltered, as variable-rate-shading hardware does
#include <array>

#include "common/image.h"
#include "common/params.h"
#include "cpu_ref/blend.h"
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/masks.h"

namespace mrr {

// tiles, step 1: the rate of every tile as the level it shades at: 0 (1×1) when the tile
// holds an edge pixel, 1 (2×2) when one of its 8 neighbours does, else 2 (4×4). `edges` is
// E on the padded full-res grid; the tile grid is ⌈padded / 16⌉ per side.
ImageU8 tileRates(const ImageU8& edges);

// tiles, step 2: S_ℓ = 1 on the level-ℓ pixels of tiles of rate ℓ (inside W×H); a_ℓ = S_ℓ.
// M_ℓ holds the rate map upsampled to level ℓ, for viewing.
std::array<MaskLevel, kLevelCount> tileMasks(const ImageU8& rates, const Constants& constants);

// The weight of tap q for full-res pixel p in the joint bilateral upsampling (SPEC §9):
// b_q × exp(−((z_q − z_p)/(σ_z z_p))²) × max(N_p·N_q, 0)^{p_n}; 0 when exactly one of p, q
// is background; b_q alone when both are.
float jointBilateralWeight(float b, bool hitP, float zp, const glm::vec3& np, bool hitQ, float zq, const glm::vec3& nq,
                           const Constants::Bilateral& params);

// The joint bilateral upsampling of level k's sub-image at full-res pixel p: the 4 bilinear
// taps weighted by jointBilateralWeight and normalised; the nearest tap (largest b_q) when
// every weight vanishes.
void jointBilateralAt(const ImageF& sub, const GBuffer& coarse, const GBuffer& full, const LevelConstants& level,
                      const Constants::Bilateral& params, int px, int py, float* out);

// Stage 5 for a peer. uniform-k: final = the joint bilateral upsampling of c_k. tiles: final
// = c_ℓ at the level-ℓ pixel holding p, ℓ the rate of p's tile. The level map says which
// level each pixel came from. With `keepStages`, ĉ_ℓ (upsampled or broadcast, 0 elsewhere),
// α_ℓ (1 where level ℓ supplies the pixel) and c'_ℓ are kept, as for the method.
// `gbuffers[ℓ]` is level ℓ's G-buffer (null where disabled); `rates` is tileRates' map (tiles only).
BlendResult composePeer(const std::array<LevelImages, kLevelCount>& levels,
                        const std::array<const GBuffer*, kLevelCount>& gbuffers, const ImageU8& rates,
                        const Constants& constants, bool keepStages);

}  // namespace mrr
