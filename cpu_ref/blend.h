#pragma once
// Stage 6 — masked-bilinear upsampling and the coarse-to-fine blend (SPEC §5, the paper's
// Eq. 1 with its erratum corrected: the right-hand side blends over the coarser composite).
#include <array>

#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"

namespace mrr {

// The 4 bilinear taps of full-res pixel (px, py) in level ℓ: u = (p + ½)/s − ½, clamped
// to the level grid; weights b_q sum to 1.
struct BilinearTaps {
  int x[4] = {0, 0, 0, 0};
  int y[4] = {0, 0, 0, 0};
  float weight[4] = {0, 0, 0, 0};
};
BilinearTaps bilinearTaps(int px, int py, const LevelConstants& level);

// ĉ_ℓ(p), â_ℓ(p) and α_ℓ(p) at one pixel. `covered` is false when Σ b_q S(q) = 0.
struct Upsampled {
  float color[4] = {0, 0, 0, 0};
  float alphaHat = 0.0f;
  float alpha = 0.0f;
  bool covered = false;
};
Upsampled upsampleAt(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level,
                     int px, int py);

// One blend step: c'_ℓ = α ĉ_ℓ + (1 − α) c'_{coarser} (SPEC §5, corrected Eq. 1).
float blendStep(float alpha, float fine, float coarserComposite);

// The final image and level map; with `keepStages`, also every ĉ_ℓ, α_ℓ and c'_ℓ.
BlendResult blendLevels(const std::array<LevelImages, kLevelCount>& levels, const Constants& constants,
                        bool keepStages = true);

}  // namespace mrr
