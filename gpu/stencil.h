#pragma once
// The port's stencil test (gpu/shaders/stencil.frag), mirroring cpu_ref/stencil.h: S_ℓ is
// written into the stencil buffer, so masked fragments are never shaded.
#include <functional>
#include <string>
#include <vector>

#include "common/image.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Writes S_ℓ (`stencilMask`, a 0/1 texture of the bound framebuffer's size) into the stencil
// buffer of the bound framebuffer and leaves the stencil test on, passing where S = 1.
// Shared by every effect pass.
// Over `cover` alone, where it is given (it holds every pixel of S_ℓ: MaskTargets::supportCover):
// the fill discards where S = 0, and a full-screen discard pass is not cheap.
void fillStencil(const GpuScene& scene, unsigned stencilMask, const Cover& cover = {});

// One effect pass under the stencil test (SPEC §4: masked fragments are never shaded): a
// fresh width×height target of `format` cleared to 0, S_ℓ written into its stencil buffer
// (over `fill` alone, when given),
// `program` in use with its inputs set by `setInputs`, one full-screen draw. The result stays
// on the GPU (0 where S_ℓ = 0). `stage` names it in GL errors.
Target drawStencilled(const GpuScene& scene, unsigned stencilMask, int width, int height, Texel format,
                      unsigned program, const std::string& stage, const std::function<void()>& setInputs,
                      const Cover& fill = {});

// The same pass under the stencil buffer an earlier pass at this level filled (`stencilled`,
// drawStencilled's target): S_ℓ is not written again (SSAO's blur after SSAO).
Target drawStencilledLike(const GpuScene& scene, const Framebuffer& stencilled, Texel format, unsigned program,
                          const std::string& stage, const std::function<void()>& setInputs);

// The host-image form of a stencilled pass (tests and the same-input checks): uploads S_ℓ,
// runs `draw` with its texture and reads `channels` channels of the result back.
ImageF withHostStencil(const ImageU8& stencil, int channels, const std::function<Target(unsigned)>& draw);

}  // namespace mrr::gpu
