#pragma once
// The port's stage 3 (gpu/shaders/masks.frag): mask pyramid, blur, stencils and the coverage
// closure on the GPU. The targets stay there for the effect and blend passes; the frame reads
// back S_ℓ (for |S_ℓ| and the never-slower rule) and, with keepStages, M_ℓ and a_ℓ too.
#include <array>
#include <memory>

#include "cpu_ref/edges.h"
#include "cpu_ref/masks.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Every enabled level's M_ℓ, a_ℓ and S_ℓ on the GPU. The later passes read `alpha[ℓ]` and
// `stencil[ℓ]` (texture names; 0 for disabled levels), drawn here or uploaded from host masks.
struct MaskTargets {
  std::array<Target, kLevelCount> maskTarget, alphaTarget, stencilTarget;  // drawn (R8, R32F, R8)
  TextureSet uploaded;                                                       // or uploaded
  std::array<unsigned, kLevelCount> alpha{}, stencil{};
  bool drawn = false;  // false: uploaded from host masks (uploadMasks)
};

// Stages 3.1–3.4 from E, channel `edgeChannel` of the texture `edges` (the padded full-res grid).
std::unique_ptr<MaskTargets> drawMasks(const GpuScene& scene, unsigned edges, int edgeChannel,
                                       const Constants& constants);

// Reads drawn masks back: every S_ℓ, and M_ℓ and a_ℓ too unless `stencilsOnly`.
std::array<MaskLevel, kLevelCount> readMasks(const MaskTargets& masks, const Constants& constants, bool stencilsOnly);

// Host masks (full, uniform-k, tiles, or a never-slower fallback) as textures for the passes.
std::unique_ptr<MaskTargets> uploadMasks(const std::array<MaskLevel, kLevelCount>& masks, const Constants& constants);

// Draw from a host E (uploaded as a texture) and read everything back: the same-input form.
std::array<MaskLevel, kLevelCount> buildMasks(const GpuScene& scene, const ImageU8& edges, const Constants& constants);

}  // namespace mrr::gpu
