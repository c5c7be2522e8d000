#pragma once
// The port's stage 3 (gpu/shaders/masks.frag): mask pyramid, blur, stencils and the coverage
// closure on the GPU, read back into the oracle's MaskLevel structures.
#include <array>

#include "cpu_ref/edges.h"
#include "cpu_ref/masks.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// `edges` is E on the padded full-res grid (uploaded as a texture).
std::array<MaskLevel, kLevelCount> buildMasks(const GpuScene& scene, const ImageU8& edges, const Constants& constants);

}  // namespace mrr::gpu
