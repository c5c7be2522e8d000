#pragma once
// The port's stage 5 (gpu/shaders/bilateral.frag), drawn with the stencil test.
#include "common/params.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

ImageF bilateralBlur(const GpuScene& scene, const ImageF& raw, const ImageU8& stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b);

// Writes S_ℓ into the stencil buffer of the bound framebuffer (stencil.frag) and leaves the
// stencil test on, passing where S = 1. Shared by every effect pass.
void fillStencil(const GpuScene& scene, const ImageU8& stencil);

}  // namespace mrr::gpu
