#pragma once
// The port's stage 5 (gpu/shaders/bilateral.frag), drawn with the stencil test.
#include "common/params.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

ImageF bilateralBlur(const GpuScene& scene, const ImageF& raw, const ImageU8& stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b);

}  // namespace mrr::gpu
