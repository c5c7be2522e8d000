#pragma once
// The port's stage 2 (gpu/shaders/edges.frag): the edge image from the level-0 G-buffer
// targets, read back into the oracle's EdgeImages.
#include "common/params.h"
#include "cpu_ref/edges.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

EdgeImages detectEdges(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings);

}  // namespace mrr::gpu
