#pragma once
// The port's stencil test (gpu/shaders/stencil.frag), mirroring cpu_ref/stencil.h: S_ℓ is
// written into the stencil buffer, so masked fragments are never shaded.
#include <functional>
#include <string>

#include "common/image.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Writes S_ℓ into the stencil buffer of the bound framebuffer and leaves the stencil test on,
// passing where S = 1. Shared by every effect pass.
void fillStencil(const GpuScene& scene, const ImageU8& stencil);

// One effect pass under the stencil test (SPEC §4: masked fragments are never shaded): a
// fresh target of S_ℓ's size cleared to 0, S_ℓ written into its stencil buffer, `program`
// in use with its inputs set by `setInputs`, one full-screen draw, and `channels` channels
// read back (0 where S_ℓ = 0). `stage` names it in GL errors.
ImageF drawStencilled(const GpuScene& scene, const ImageU8& stencil, unsigned program, int channels,
                      const std::string& stage, const std::function<void()>& setInputs);

}  // namespace mrr::gpu
