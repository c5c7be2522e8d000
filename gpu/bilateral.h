#pragma once
// The port's stage 4, SSAO's blur (gpu/shaders/bilateral.frag), drawn with the stencil test.
#include "common/params.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// The mask-aware blur of the raw sub-image (`raw`, one channel) where S_ℓ (`stencil`, a 0/1
// texture) is set, into a fresh R32F target kept on the GPU. Null when the radius is 0 (no
// blur: the caller keeps `raw`). With `rawTarget` (the effect pass's target, drawn under S_ℓ),
// its stencil buffer is reused rather than filled again.
Target drawBilateral(const GpuScene& scene, unsigned raw, unsigned stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b, const Framebuffer* rawTarget = nullptr);

// The same from host images, read back.
ImageF bilateralBlur(const GpuScene& scene, const ImageF& raw, const ImageU8& stencil, const Framebuffer& gbuffer,
                     const Constants::Bilateral& b);

}  // namespace mrr::gpu
