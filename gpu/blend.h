#pragma once
// The port's stage 5 (gpu/shaders/blend.frag): one full-res pass per enabled level, coarse to
// fine, each writing ĉ_ℓ, α_ℓ, c'_ℓ and the level map; read back into the oracle's BlendResult.
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
// plain render) one pass for all levels (blend.frag FINAL_ONLY, bit-identical), and only the
// final image and level map leave the GPU, as the oracle keeps only those then. With
// `edgeBlocks` (MaskTargets::edgeBlocks), that pass blends the finer levels only near edges;
// `widenedBy` (MaskTargets::widenedBy, null: none) adds each level's widening (SPEC §12) to the reach.
// `finalOnGpu`: where the final image stays on the GPU for the passes after (the shaded image).
BlendResult blendLevels(const GpuScene& scene, const std::array<LevelTextures, kLevelCount>& levels, int channels,
                        const Constants& constants, bool keepStages = true, const ImageU8* edgeBlocks = nullptr,
                        GpuImage* finalOnGpu = nullptr, const std::array<int, kLevelCount>* widenedBy = nullptr);

}  // namespace mrr::gpu
