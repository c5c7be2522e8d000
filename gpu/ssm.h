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
               const Cover& fill = {});

// The same from a host S_ℓ, read back.
ImageF renderSsm(const GpuScene& scene, const Framebuffer& gbuffer, const ImageU8& stencil, const ShadowMap& map,
                 unsigned mapTexture, const View& view, const LevelConstants& level, const Constants::Ssm& ssm);

// SPEC §11: the never-slower rule's sample of where PCF is paid (ssm.frag with PCF_SAMPLE), on
// the GPU (R8, the byte / 255): ⌈W/8⌉×⌈H/8⌉, what level-0 pixel (8x + 4, 8y + 4) pays (kPcfSample…).
// Mirrors cpu_ref/ssm.cpp: pcfSample, on the port's own G-buffer and shadow map.
Target drawPcfSample(const GpuScene& scene, const Framebuffer& gbuffer0, const ShadowMap& map, unsigned mapTexture,
                     const View& view, const Constants::Ssm& ssm);
// Its bytes read back (the bytes common/shader_constants.h names), for --stages and probe.
ImageU8 readPcfSample(const Framebuffer& sample);

}  // namespace mrr::gpu
