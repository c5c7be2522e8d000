#pragma once
// Stage 5 — masked-bilinear upsampling and the coarse-to-fine blend (SPEC §5, the paper's
// Eq. 1 with its erratum corrected: the right-hand side blends over the coarser composite).
// The steps are numbered as in gpu/shaders/blend.frag, which computes the same function:
//   1. the bilinear taps of u = (p − ⌊s/2⌋)/s        (bilinearTapsReference, tapAxis)
//   2. masked bilinear ĉ and â over the four taps    (upsampleReference, upsampleImpl)
//   3. α = min(â·w, 1) where a tap is rendered, else 0
//   4. c'_ℓ = α ĉ_ℓ + (1 − α) c'_coarser             (blendStep)
//   5. the level map: the finest level with α > 0
// blendReference is the readable rule, one pixel at a time in that order; blendLevels is the
// fast path, equal to it bit for bit (tests/oracle/invariants_test.cpp, BlendFastPathsMatchTheReference).
#include <array>

#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"

namespace mrr {

// The 4 bilinear taps of full-res pixel (px, py) in level ℓ: u = (p − ⌊s/2⌋)/s, clamped
// to the level grid; weights b_q sum to 1.
struct BilinearTaps {
  int x[4] = {0, 0, 0, 0};
  int y[4] = {0, 0, 0, 0};
  float weight[4] = {0, 0, 0, 0};
};
BilinearTaps bilinearTaps(int px, int py, const LevelConstants& level);

// Step 1, readable: the shader's floor form, u = (p − ⌊s/2⌋)/s, f = floor(u), t = u − f. Every
// quantity is a small dyadic rational, so float gives exactly what bilinearTaps' integer
// shift-and-mask gives (tested equal at every pixel).
BilinearTaps bilinearTapsReference(int px, int py, const LevelConstants& level);

// ĉ_ℓ(p), â_ℓ(p) and α_ℓ(p) at one pixel. `covered` is false when Σ b_q S(q) = 0.
struct Upsampled {
  float color[4] = {0, 0, 0, 0};
  float alphaHat = 0.0f;
  float alpha = 0.0f;
  bool covered = false;
};
Upsampled upsampleAt(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha, const LevelConstants& level,
                     int px, int py);

// Steps 1–3, readable: ĉ_ℓ(p), â_ℓ(p) and α_ℓ(p) from bilinearTapsReference's taps.
Upsampled upsampleReference(const ImageF& sub, const ImageU8& stencil, const ImageF& alpha,
                            const LevelConstants& level, int px, int py);

// Step 4. One blend step: c'_ℓ = α ĉ_ℓ + (1 − α) c'_{coarser} (SPEC §5, corrected Eq. 1).
float blendStep(float alpha, float fine, float coarserComposite);

// Steps 1–5, readable: every pixel, every enabled level from the coarsest (which covers every
// pixel: α = 1 there) to the finest; keeps every ĉ_ℓ, α_ℓ and c'_ℓ.
BlendResult blendReference(const std::array<LevelImages, kLevelCount>& levels, const Constants& constants);

// Fast path, equal to blendReference: the final image and level map; with `keepStages`, also
// every ĉ_ℓ, α_ℓ and c'_ℓ.
BlendResult blendLevels(const std::array<LevelImages, kLevelCount>& levels, const Constants& constants,
                        bool keepStages = true);

// SPEC §12.5 step 1, R(p): at each full-res pixel of W×H, the coarsest level the blend reads, the
// finest enabled level whose α is 1 there (step 3; nothing coarser shows: blendStep(1, f, c) = f),
// else the coarsest enabled level: the base blendLevels' final-only path starts from. On the
// padded full-res grid, 0 outside W×H. Reads each level's S and a alone (`sub` may be null).
ImageU8 blendReach(const std::array<LevelImages, kLevelCount>& levels, const Constants& constants);

}  // namespace mrr
