#pragma once
// The port's stage 2 (gpu/shaders/edges.frag): the edge image from the level-0 G-buffer
// targets, read back into the oracle's EdgeImages.
#include "common/params.h"
#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// `shadowLitTexture` (the one-tap test per pixel, lit in R: gpu/shadowmap.h drawShadowTest or an
// uploaded image) enables the shadow kind; 0 for SSAO and SSGI, as the oracle's null shadowLit.
// The result stays on the GPU: RGBA8 target 0 holds (normal, depth, background, E), target 1
// the shadow kind (with the shadow kind on). With `combinedOnly`, one R8 target holds E alone
// (what the masks need; 1/4 of the bytes). edgeChannel: E's channel in target 0.
Target drawEdges(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings,
                 unsigned shadowLitTexture = 0, bool combinedOnly = false);
inline int edgeChannel(bool combinedOnly) { return combinedOnly ? 0 : 3; }

// Reads drawEdges' targets back into the oracle's structure.
EdgeImages readEdges(const Framebuffer& edges);

// The never-slower rule's edge sample (SPEC §11; cpu_ref/edges.h edgeSample) on the GPU: E at the
// 8 pixels of each 8×8 block's diagonal, side by side in a row (R8, ⌈W/8⌉·8 × ⌈H/8⌉); a block is
// in Ê where any of its eight is 1 (gpu/rule.cpp counts it so). The same inputs as drawEdges.
Target drawEdgeSample(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings,
                      unsigned shadowLitTexture = 0);
// Ê read back, one byte (0/1) per block.
ImageU8 readEdgeSample(const Framebuffer& diagonals);

// Draw and read back in one call.
EdgeImages detectEdges(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings,
                       unsigned shadowLitTexture = 0);

}  // namespace mrr::gpu
