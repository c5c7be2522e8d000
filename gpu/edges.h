#pragma once
// The port's stage 2 (gpu/shaders/edges.frag): the edge image from the level-0 G-buffer
// targets, read back into the oracle's EdgeImages.
#include "common/params.h"
#include "cpu_ref/edges.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// `shadowLitTexture` (the one-tap test per pixel, lit in R: gpu/shadowmap.h drawShadowTest or an
// uploaded image) enables the shadow kind; 0 for SSAO and SSGI, as the oracle's null shadowLit.
EdgeImages detectEdges(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings,
                       unsigned shadowLitTexture = 0);

}  // namespace mrr::gpu
