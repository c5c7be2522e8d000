#pragma once
// `mrr probe`: follows one full-res pixel through every stage of a rendered frame — the
// per-pixel mask debugger. Values are read from the FrameResult, and the decisions that
// produced them (edge derivatives, bilinear taps, SSAO sample counts) are recomputed by the
// same functions the stages use, so what it prints is what the pipeline did.
#include <nlohmann/json.hpp>

#include <string>

#include "cpu_ref/masks.h"
#include "cpu_ref/pipeline.h"

namespace mrr {

// SPEC §12.3: why level ℓ covers a level pixel q (S_ℓ(q) = 1), or why not. The first that holds:
// the coarsest enabled level (a ≡ 1; "fallback" when the never-slower rule fell back to full);
// geometry: (G ∗ L(M_ℓ))(q) > 0, M_ℓ the pyramid of E alone; effect: (G ∗ L(M'_ℓ))(q) > 0, M'_ℓ
// after §12's widening; marks: (G ∗ (L(M'_ℓ) ∨ L(marks_ℓ)))(q) > 0 (§12.2); closure: S_ℓ(q) = 1
// from a finer level (§3 step 4). Not covered: limit, when an arm without §13's limit L would
// reach q; else none.
enum class Coverage { None, Geometry, Effect, Marks, Closure, Coarsest, Fallback, Limit, Trim };
const char* coverageName(Coverage coverage);

// The arms, recomputed by the oracle's functions on a frame's own inputs (its E, level-0
// G-buffer, shadow map, level limit and coarser sub-images); `active` only for modes mrr and
// mrr-effect with edges. a* are per enabled level but the coarsest; marks only with τ > 0.
struct CoverageArms {
  bool active = false, limited = false;
  ImageF footprint;  // F, full res (mrr-effect)
  MaskStages stages;
  Masks widened;     // .mask: M'_ℓ before the limit (mrr: M_ℓ)
  std::array<ImageU8, kLevelCount> marks;
  std::array<ImageF, kLevelCount> aGeometry, aWidened, aMarks, aGeometryUnlimited, aWidenedUnlimited;
};
CoverageArms coverageArms(const FrameResult& frame);
Coverage coverageReason(const CoverageArms& arms, const FrameResult& frame, int level, int qx, int qy);

nlohmann::json probePixel(const FrameResult& frame, int x, int y);
std::string formatProbe(const nlohmann::json& probe);
// SPEC §12.3: one level's "why" object (probe's levels[ℓ].why) in one line.
std::string formatWhy(const nlohmann::json& why);

}  // namespace mrr
