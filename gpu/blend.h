#pragma once
// The port's stage 5 (gpu/shaders/blend.frag): one full-res pass per enabled level, coarse to
// fine, each writing ĉ_ℓ, α_ℓ, c'_ℓ and the level map, read back into the oracle's BlendResult
// (keepStages); or one pass for every level, kept on the GPU.
#include <array>

#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// One level's inputs to stage 5 on the GPU (texture names): c_ℓ, S_ℓ and a_ℓ.
struct LevelTextures {
  unsigned sub = 0, stencil = 0, alpha = 0;
};

// `channels`: c_ℓ's (1 or 3). With `keepStages`, one pass per level, and every level's ĉ_ℓ,
// α_ℓ and c'_ℓ read back beside the final image and level map. Without it (the benchmark, a
// plain render) one pass for all levels (blend.frag FINAL_ONLY, bit-identical), nothing read
// back: the result is empty and the final image stays in `finalOnGpu` (target 0; the level map,
// R8, in its target 1) for the passes after and for the host when it asks. With `nearBlocks`
// (MaskTargets::blendNear, a block map on the GPU: the 8×8 blocks within a finer level's reach
// of an edge block, its widening included), that pass blends the finer levels only there; the
// coarsest level's S is then known to be 1 everywhere (drawn masks).
BlendResult blendLevels(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, int channels,
                        const Constants& constants, bool keepStages = true, const BlockMap& nearBlocks = {},
                        GpuImage* finalOnGpu = nullptr);

// SPEC §12.5 step 1 (blend.frag REACH, cpu_ref/blend.cpp blendReach): R(p), the coarsest level
// the blend reads at each full-res pixel, from the levels' `stencil` and `alpha` alone (`sub` is
// not read): ℓ/255 in an R8 target on the padded full-res grid, 0 outside W×H. With `nearBlocks`
// (MaskTargets::blendNear) drawn over those blocks alone, C elsewhere (far from every edge).
Target blendReach(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, const Constants& constants,
                  const BlockMap& nearBlocks = {});

}  // namespace mrr::gpu
