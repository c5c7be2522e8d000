#pragma once
// The port's stencil test (gpu/shaders/stencil.frag), mirroring cpu_ref/stencil.h: S_ℓ is
// written into the stencil buffer, so masked fragments are never shaded.
#include "common/image.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Writes S_ℓ into the stencil buffer of the bound framebuffer and leaves the stencil test on,
// passing where S = 1. Shared by every effect pass.
void fillStencil(const GpuScene& scene, const ImageU8& stencil);

}  // namespace mrr::gpu
