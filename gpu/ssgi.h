#pragma once
// The port's stage 4 for indirect light (gpu/shaders/ssgi.frag), mirroring cpu_ref/ssgi.cpp:
// each level's direct light (every pixel: any may be a sender), then the gather, drawn with
// the stencil test so it runs only where S_ℓ is set.
#include "common/camera.h"
#include "common/params.h"
#include "common/scene.h"
#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// The direct light each pixel of a level sends, albedo × max(N·L, 0) × one-tap shadow × light
// colour (background 0), into `target` (1 colour target, level-sized): kept on the GPU.
void drawDirectLight(const GpuScene& scene, const Framebuffer& gbuffer, const ShadowMap& map, unsigned mapTexture,
                     const View& view, const DirectionalLight& light, float biasTexels, const Framebuffer& target);

// Draw and read back (RGB): the port's directLight.
ImageF directLight(const GpuScene& scene, const Framebuffer& gbuffer, const ShadowMap& map, unsigned mapTexture,
                   const View& view, const DirectionalLight& light, float biasTexels);

// The raw sub-image c_ℓ, indirect RGB (RGBA32F, 0 where S_ℓ = 0), from the level's G-buffer
// targets, S_ℓ (a 0/1 texture) and its direct light (a texture: drawDirectLight's target, or an
// uploaded image): kept on the GPU.
Target drawSsgi(const GpuScene& scene, const Framebuffer& gbuffer, unsigned directTexture, unsigned stencil,
                const View& view, const LevelConstants& level, const Constants::Ssgi& ssgi,
                const Cover& fill = {});

// The same from a host S_ℓ, read back (RGB).
ImageF renderSsgi(const GpuScene& scene, const Framebuffer& gbuffer, unsigned directTexture, const ImageU8& stencil,
                  const View& view, const LevelConstants& level, const Constants::Ssgi& ssgi);

}  // namespace mrr::gpu
