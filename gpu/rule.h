#pragma once
// The never-slower rule's counts and the frame's shaded-pixel counts on the GPU (SPEC §11;
// gpu/shaders/rule.frag, summed by gpu/counts.h): what common/frame.h's countHits,
// countEdgeSample, countForRule, countShadedPixels and countHitPixels count on the host from
// images, here from the port's own textures, read as a few integers in one small read per call
// (docs/port.md, "What a frame costs the host"). tests/gpu/rule_counts_test.cpp holds each to the
// host's count on the read-back images.
#include <array>
#include <functional>

#include "common/cost_model.h"
#include "common/frame.h"
#include "common/params.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// The edge sample countEarly tests itself (rule.frag step 1 WITH_SAMPLE: SPEC §2's edge test at
// each 8×8 block's diagonal pixels, from the G-buffer rows it reads for the hits): the thresholds
// and, SSM, the one-tap shadow test's target (0: no shadow edges). No settings: no sample.
struct EdgeSampleInputs {
  const EdgeSettings* settings = nullptr;
  unsigned shadowLit = 0;
};

// countHits into `counts` (H, H_a, H_p, F, B_ℓ) from level 0's G-buffer and, SSM, the PCF sample
// (`pcfSample`: ssm.frag PCF_SAMPLE's R8 target, or 0: none). Then, with `sample` and where
// `wantSample(counts)` says so, countEdgeSample's Ê, R_ℓ and their hit pixels; returns whether it
// counted them. Both in one small read. With `hitBits`, step 1's target comes back (its counts2
// holds each 8×8 block's 64 hit bits in z, w) for countStencils.
bool countEarly(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned pcfSample, const EdgeSampleInputs& sample,
                const Constants& constants, FrameCounts& counts,
                const std::function<bool(const FrameCounts&)>& wantSample,
                Target* hitBits = nullptr);

// countForRule into `counts` (|S_ℓ|, |S_ℓ ∩ hit|, ∩ searched, ∩ pcf per shaded level) from the
// stencils' textures (R8, 0 for a disabled level). One small read. With `hitBits` (countEarly's
// counts2) the hit of a level pixel's sample comes from its block's bits, not level 0's G-buffer:
// the same counts, 1 fetch a block instead of one a stencilled pixel.
void countStencils(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned pcfSample,
                   const std::array<unsigned, kLevelCount>& stencils, const Constants& constants, FrameCounts& counts,
                   unsigned hitBits = 0);

// What the report says of the frame's stencils, into f (FrameResult::countShadedPixels and
// countHitPixels: |S_ℓ| and its 4×2 blocks per enabled level, the ideal speedups). H is
// `hitPixels` where the rule counted it (≥ 0), else counted here. One small read.
// With `finalCounts` (f.counts so far), countStencils on the same stencils too, in the same read
// (SPEC §12.4's predicted time per level on the final stencils; H must then be known: 8 targets).
void countShaded(const GpuScene& scene, const Framebuffer& gbuffer0, const std::array<unsigned, kLevelCount>& stencils,
                 FrameResult& f, int64_t hitPixels = -1, FrameCounts* finalCounts = nullptr, unsigned pcfSample = 0, unsigned hitBits = 0);

}  // namespace mrr::gpu
