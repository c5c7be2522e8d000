#pragma once
// The port's peers (gpu/shaders/peers.frag), mirroring cpu_ref/peers.cpp: tiles' stage 3 (the
// rate map and the per-level masks) and stage 5 for every peer (the joint bilateral upsampling
// of uniform-k, the tiles' broadcast), on the GPU: nothing comes back unless the frame keeps its
// stages (readTileRates, readTileMasks; composePeer with keepStages). uniform-k's stage 3 is a
// constant stencil (gpu/masks.h drawUniformMasks).
#include <array>
#include <memory>

#include "common/frame.h"
#include "gpu/gbuffer.h"
#include "gpu/masks.h"

namespace mrr::gpu {

// tiles, steps 1–2: each 16×16 tile's rate, 0 (1×1), 1 (2×2) or 2 (4×4), from E: channel
// `edgeChannel` of the texture `edges` (the padded full-res grid, width×height); the result (R32F
// in r) is on the ⌈padded / 16⌉ tile grid. With `limit` (limit.frag's target texture; 0: none),
// SPEC §13 step 6 too (limitTileRates).
Target drawTileRates(const GpuScene& scene, unsigned edges, int edgeChannel, int width, int height, unsigned limit = 0);
// The rates read back (--stages, probe, compare; the report's tile counts).
ImageU8 readTileRates(const Framebuffer& rates);

// tiles, step 3: S_ℓ = a_ℓ = [rate == ℓ and the level pixel's block starts inside W×H], for every
// enabled level (R8 targets; the rates stay in MaskTargets::tileRates).
std::unique_ptr<MaskTargets> drawTileMasks(const GpuScene& scene, Target rates, const Constants& constants);
// Their host images, as the oracle's tileMasks: M_ℓ = the rate of the pixel's tile (from `rates`,
// read back), S_ℓ read back, a_ℓ = S_ℓ.
std::array<MaskLevel, kLevelCount> readTileMasks(const MaskTargets& masks, const ImageU8& rates, const Constants& constants);

// Stage 5 for a peer at full res W×H, into `composed` (the final value in target 0, the level it
// came from in target 1, R32F); with `keepStages`, read back with ĉ_ℓ, α_ℓ and c'_ℓ of every enabled
// level as the oracle's hard switch (else the result is empty: the caller reads `composed` when
// it asks). `subs[ℓ]` is c_ℓ's texture (`channels` channels), `gbuffers[ℓ]` level ℓ's G-buffer
// targets (uniform-k reads levels 0 and k); `rates` is drawTileRates' texture (tiles only).
BlendResult composePeer(const GpuScene& scene, const std::array<unsigned, kLevelCount>& subs, int channels,
                        const std::array<const Framebuffer*, kLevelCount>& gbuffers, unsigned rates,
                        const Constants& constants, bool keepStages, Target& composed);
// The final image and level map of composePeer's target.
void readComposed(const Framebuffer& composed, int channels, BlendResult& out);

}  // namespace mrr::gpu
