#pragma once
// mrr-effect (SPEC §12): the effect's footprint, known before shading, widens each
// level's edge mask; §12.2's a-posteriori term refines it from the coarser result. The port
// mirrors each function: gpu/effect_masks.h, gpu/shaders/effect_masks.frag,
// refinement_marks.frag and refine_masks.frag.
#include "common/camera.h"
#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"

namespace mrr {

// SPEC §12 step 1: the footprint F at each full-res pixel, in full-res pixels: at an edge pixel
// (E = 1) on geometry, scale × the effect's reach projected at its view depth z (SSAO, SSGI:
// R · f / z; SSM: the one-tap penumbra bound (d_receiver − d_map)₊ · 2 tan(θ/2) · f / z at a
// receiver facing the light); 0 elsewhere. `map` is read for SSM only (may be null otherwise).
ImageF effectFootprint(const GBuffer& g, const ImageU8& edges, const View& view, const ShadowMap* map,
                       const Constants& c);

// SPEC §12 step 2: level ℓ's reach, in level pixels, where M_ℓ = 1: min(cap, ⌊F_ℓ / s_ℓ + ½⌋) with
// F_ℓ the max of F over the pixel's s_ℓ × s_ℓ block; −1 where M_ℓ = 0.
Image<int16_t> levelReach(const ImageU8& mask, const ImageF& footprintMax, int scale, int cap);

// SPEC §12 step 3: M'(p) = 1 where some q with M(q) = 1 lies within reach K(q) of p along both
// axes (a square of side 2K(q) + 1 around q), clipped to the level. Exact, made separably.
ImageU8 dilateByReach(const ImageU8& mask, const Image<int16_t>& reach);

// SPEC §12.3, the ablation's effect-only arm: the pixels the widening adds, M'_ℓ ∧ ¬M_ℓ.
ImageU8 wideningOnly(const ImageU8& widened, const ImageU8& geometry);

// SPEC §12.2 step 1's v(q): the range of c over q's 3×3 neighbourhood of S = 1 hit pixels, the
// largest over the channels; −1 where q itself is not such a pixel (never marked).
float localRange(const ImageF& c, const ImageU8& stencil, const ImageU8& hit, int x, int y);

// SPEC §12.2 step 1's v at every pixel of the level (−1 where q is not a shaded hit pixel), made
// separably: per channel the min and max over each pixel's row of three, the excluded pixels
// neutral (+∞, −∞), then over the column of three of those. min and max are exact and the
// centre is always in both, so it equals localRange at every pixel
// (EffectMasks.SeparableRangeEqualsTheWholeNeighbourhood). `localRanges` is the readable form.
ImageF localRanges(const ImageF& c, const ImageU8& stencil, const ImageU8& hit);
ImageF localRangesSeparable(const ImageF& c, const ImageU8& stencil, const ImageU8& hit);

// SPEC §12.2, a posteriori, step 1: the marks at a finer level from its next coarser level's
// result c (SSAO: after the bilateral blur): the local range v(q) = max − min of c over q's 3×3
// neighbourhood of shaded (S = 1) hit pixels, the largest over the channels; a finer pixel p is
// marked where v(⌊p / ratio⌋) > τ. `finerWidth` × `finerHeight` is the finer level's grid.
ImageU8 refinementMarks(const ImageF& coarser, const ImageU8& coarserStencil, const ImageU8& coarserHit, int ratio,
                        int finerWidth, int finerHeight, float tau);
// Its two parts: 1. [v(q) > τ] from v (localRangesSeparable); 2. each finer pixel p takes the mark
// of its parent (min(⌊p_x / ratio⌋, w_n − 1), min(⌊p_y / ratio⌋, h_n − 1)). With SPEC §12.4's budget
// step 1 is the selection (common/effect_budget.h) instead.
ImageU8 variesAbove(const ImageF& range, float tau);
ImageU8 parentMarks(const ImageU8& varies, int ratio, int finerWidth, int finerHeight);

// SPEC §12.2 step 2: M_ℓ ∨= marks; a_ℓ = G(σ_ℓ²) ∗ M_ℓ again; S_ℓ ∨= [a_ℓ > 0] (what the closure
// gave S_ℓ from finer levels is kept). Not for the coarsest enabled level (a ≡ 1).
// `refineMasksReference` is the readable rule (the whole level blurred again); `refineMasks`, the
// one the pipeline runs, blurs again only where a new bit of M_ℓ reaches, with blurMask's own
// per-pixel sums: the same bits (EffectMasks.RefineMasksFastPathMatchesTheReference).
void refineMasksReference(MaskLevel& level, const ImageU8& marks, const LevelConstants& lc);
void refineMasks(MaskLevel& level, const ImageU8& marks, const LevelConstants& lc);

}  // namespace mrr
