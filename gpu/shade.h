#pragma once
// The port's stage 6 (gpu/shaders/shade.frag), mirroring cpu_ref/shade.cpp: the shaded image
// for viewing, drawn from the level-0 G-buffer targets and the final effect buffer on the GPU.
#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// W×H linear RGB (RGBA32F, kept on the GPU: read(0, 3) when the host asks). `effect` is the
// final effect buffer's texture (W×H), `shadowLit` the one-tap test's (SSGI; 0 otherwise).
Target drawShade(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned effect, unsigned shadowLit,
                 const View& view, const DirectionalLight& light, const Constants& constants);

}  // namespace mrr::gpu
