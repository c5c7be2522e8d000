#pragma once
// The port's stage 6 (gpu/shaders/blend.frag): one full-res pass per enabled level, coarse to
// fine, each writing ĉ_ℓ, α_ℓ and c'_ℓ; read back into the oracle's BlendResult.
#include <array>

#include "cpu_ref/blend.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

BlendResult blendLevels(const GpuScene& scene, const std::array<LevelImages, kLevelCount>& levels,
                        const Constants& constants);

}  // namespace mrr::gpu
