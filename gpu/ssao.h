#pragma once
// The port's stage 4 for SSAO (gpu/shaders/ssao.frag), drawn with the stencil test: S_ℓ is
// written into the stencil buffer (stencil.frag), then the effect runs only where it is set.
#include "common/camera.h"
#include "common/params.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// The raw sub-image c_ℓ (R32F, 0 where S_ℓ = 0), from the level's G-buffer targets and S_ℓ
// (a 0/1 texture): kept on the GPU. `fill`: see drawStencilled.
Target drawSsao(const GpuScene& scene, const Framebuffer& gbuffer, unsigned stencil, const View& view,
                const LevelConstants& level, const Constants::Ssao& ssao,
                const Cover& fill = {});

// The same from a host S_ℓ, read back.
ImageF renderSsao(const GpuScene& scene, const Framebuffer& gbuffer, const ImageU8& stencil, const View& view,
                  const LevelConstants& level, const Constants::Ssao& ssao);

// pixelHash(x, y, level) computed by the GLSL of common.glsl over a width×height grid.
std::vector<uint32_t> hashGrid(const GpuScene& scene, int width, int height, int level);

}  // namespace mrr::gpu
