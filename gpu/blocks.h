#pragma once
// Block maps on the GPU (gpu/shaders/blocks.frag): R8 images on a grid of blocks, 1 where a block
// may hold a pass's work. gpu/masks.cpp makes them from E's own pyramid (M_2 is the 4×4 grid's
// map, M_3 the 8×8 grid's), dilates them by a blur's or a widening's reach and unites them;
// the passes are then drawn over their runs (Cover::blocksOf, blocks.geom). The host never reads
// them: they replace the block maps it made from M_2 read back (common/frame.h nearBlocks and
// gpu/masks.h blocksOf, which tests/gpu/mask_rects_test.cpp holds them to).
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// The blocks within `across` blocks across and `down` down of a set block of `map` (a box,
// clamped to the grid: nearBlocks with across = ceil(r / blockSize)); with `also` (the same
// grid), OR-ed with it.
Target dilateBlocks(const GpuScene& scene, const Framebuffer& map, int across, int down, const Framebuffer* also = nullptr);
// The union of two maps of one grid.
Target uniteBlocks(const GpuScene& scene, const Framebuffer& a, const Framebuffer& b);
// The map of `factor`×`factorY` blocks of `map` (blocksOf: a block is set where any under it is;
// factorY < 0: `factor`).
Target poolBlocks(const GpuScene& scene, const Framebuffer& map, int factor, int factorY = -1);
// ceil(radius / blockSize): how many blocks a reach of `radius` pixels spans (nearBlocks' d).
inline int blocksWithin(int radius, int blockSize) { return (radius + blockSize - 1) / blockSize; }

}  // namespace mrr::gpu
