#pragma once
// The port's stage 4 for soft shadows (gpu/shaders/ssm.frag), mirroring cpu_ref/ssm.cpp: PCSS
// on the light's shadow map, drawn with the stencil test (S_ℓ in the stencil buffer), so the
// effect runs only where it is set.
#include "common/camera.h"
#include "common/params.h"
#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// The raw sub-image c_ℓ = V (R32F, 0 where S_ℓ = 0), from the level's G-buffer targets, S_ℓ
// (a 0/1 texture) and the map (`map` gives the frame, `mapTexture` the depths on the GPU).
Target drawSsm(const GpuScene& scene, const Framebuffer& gbuffer, unsigned stencil, const ShadowMap& map,
               unsigned mapTexture, const View& view, const Constants::Ssm& ssm,
               const std::vector<glm::ivec4>* fillRects = nullptr);

// The same from a host S_ℓ, read back.
ImageF renderSsm(const GpuScene& scene, const Framebuffer& gbuffer, const ImageU8& stencil, const ShadowMap& map,
                 unsigned mapTexture, const View& view, const LevelConstants& level, const Constants::Ssm& ssm);

// SPEC §11: the never-slower rule's sample of where PCF is paid (ssm.frag with PCF_SAMPLE),
// read back: ⌈W/8⌉×⌈H/8⌉, what level-0 pixel (8x + 4, 8y + 4) pays (kPcfSample…). Mirrors
// cpu_ref/ssm.cpp: pcfSample, on the port's own G-buffer and shadow map.
ImageU8 drawPcfSample(const GpuScene& scene, const Framebuffer& gbuffer0, const ShadowMap& map, unsigned mapTexture,
                      const View& view, const Constants::Ssm& ssm);

}  // namespace mrr::gpu
