#pragma once
// The port's peers (gpu/shaders/peers.frag), mirroring cpu_ref/peers.cpp: tiles' stage 3 (the
// rate map and the per-level masks) and stage 5 for every peer (the joint bilateral upsampling
// of uniform-k, the tiles' broadcast), read back into the oracle's structures. uniform-k's
// stage 3 is a constant stencil: the pipeline calls common/frame.h's uniformMasks (it reads no image).
#include <array>

#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// tiles, steps 1–2: each 16×16 tile's rate, 0 (1×1), 1 (2×2) or 2 (4×4), from E on the GPU:
// channel `edgeChannel` of the texture `edges` (the padded full-res grid, width×height); the
// result is on the ⌈padded / 16⌉ tile grid.
ImageU8 tileRates(const GpuScene& scene, unsigned edges, int edgeChannel, int width, int height);

// tiles, step 3: M_ℓ = rate, S_ℓ = a_ℓ = [rate == ℓ and the level pixel's block starts inside
// W×H], for every enabled level (the rate map uploaded as a texture).
std::array<MaskLevel, kLevelCount> tileMasks(const GpuScene& scene, const ImageU8& rates, const Constants& constants);

// Stage 5 for a peer at full res W×H: final and level map; with `keepStages`, ĉ_ℓ, α_ℓ and c'_ℓ
// of every enabled level as the oracle's hard switch. `subs[ℓ]` is c_ℓ's texture (`channels`
// channels), `gbuffers[ℓ]` level ℓ's G-buffer targets (uniform-k reads levels 0 and k);
// `rates` is tileRates' map (tiles only).
BlendResult composePeer(const GpuScene& scene, const std::array<unsigned, kLevelCount>& subs, int channels,
                        const std::array<const Framebuffer*, kLevelCount>& gbuffers, const ImageU8& rates,
                        const Constants& constants, bool keepStages, GpuImage* finalOnGpu = nullptr);

}  // namespace mrr::gpu
