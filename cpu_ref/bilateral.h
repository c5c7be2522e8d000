#pragma once
// Stage 4 (SSAO) — mask-aware bilateral blur of a sub-image (SPEC §4): taps weighted by a spatial
// Gaussian × depth similarity × normal similarity × S(q), normalised over valid taps only,
// so nothing leaks in from a pixel that was not rendered.
#include "common/image.h"
#include "common/params.h"
#include "cpu_ref/gbuffer.h"

namespace mrr {

// max(cosine, 0)^power, the normal similarity (SPEC §4); `cosine` is already clamped.
float normalSimilarity(float cosine, float power);

// Weight of tap q for centre p (0 when q is unrendered or background).
float bilateralWeight(const GBuffer& g, const ImageU8& stencil, const Constants::Bilateral& b, float spatial,
                      int px, int py, int qx, int qy);

ImageF bilateralBlur(const ImageF& image, const ImageU8& stencil, const GBuffer& g, const Constants::Bilateral& b);

}  // namespace mrr
