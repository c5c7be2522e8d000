#pragma once
// Stage 6 — masked-bilinear upsampling and the coarse-to-fine blend (SPEC §5, the paper's
// Eq. 1 with its erratum corrected: the right-hand side blends over the coarser composite).
#include <array>

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

// α_ℓ(p) alone (the same value upsampleAt returns), for the final-only blend.
float alphaAt(const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level, int px, int py);

// One blend step: c'_ℓ = α ĉ_ℓ + (1 − α) c'_{coarser} (SPEC §5, corrected Eq. 1).
float blendStep(float alpha, float fine, float coarserComposite);

struct BlendResult {
  std::array<ImageF, kLevelCount> upsampled;  // ĉ_ℓ on W×H (empty for disabled levels, or unless kept)
  std::array<ImageF, kLevelCount> alpha;      // α_ℓ on W×H
  std::array<ImageF, kLevelCount> composite;  // c'_ℓ on W×H
  ImageF final;                               // c'_finest
  ImageU8 levelMap;                           // finest level with α > 0 at each pixel

  // W×H final (`channels`) and level map, unfilled: the caller writes every pixel of both.
  // With `keepStages`, also ĉ_ℓ, α_ℓ and c'_ℓ for every enabled level, zero-filled.
  static BlendResult allocate(const Constants& constants, int channels, bool keepStages);
};

struct LevelImages {
  const ImageF* sub = nullptr;       // c_ℓ (after the bilateral blur)
  const ImageU8* stencil = nullptr;  // S_ℓ
  const ImageF* alpha = nullptr;     // a_ℓ
};

// The final image and level map; with `keepStages`, also every ĉ_ℓ, α_ℓ and c'_ℓ.
BlendResult blendLevels(const std::array<LevelImages, kLevelCount>& levels, const Constants& constants,
                        bool keepStages = true);

}  // namespace mrr
