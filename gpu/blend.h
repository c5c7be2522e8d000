#pragma once
// The port's stage 6 (gpu/shaders/blend.frag): one full-res pass per enabled level, coarse to
// fine, each writing ĉ_ℓ, α_ℓ and c'_ℓ; read back into the oracle's BlendResult.
#include <array>

#include "cpu_ref/blend.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Without `keepStages` (the benchmark) only the final image and each level's α (for the
// level map) are read back, as the oracle keeps only the final image and level map then.
BlendResult blendLevels(const GpuScene& scene, const std::array<LevelImages, kLevelCount>& levels,
                        const Constants& constants, bool keepStages = true);

}  // namespace mrr::gpu
