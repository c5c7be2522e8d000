#pragma once
// Block maps on the GPU (gpu/shaders/blocks.frag): R8 images on a grid of blocks, 1 where a block
// may hold a pass's work. gpu/masks.cpp makes them from E's own pyramid (M_2 is the 4×4 grid's
// map, M_3 the 8×8 grid's): every cover of a frame's masks, blend and stencil fills in two passes
// (blockMaps), and the a-posteriori term's from its marks; the passes are then drawn over their
// runs (Cover::blocksOf, blocks.geom). The host never reads them: they replace the block maps it
// made from M_2 read back (common/frame.h nearBlocks and gpu/masks.h blocksOf, which
// tests/gpu/mask_rects_test.cpp holds them to).
#include <vector>

#include "gpu/gbuffer.h"

namespace mrr::gpu {

// The blocks within `across` blocks across and `down` down of a set block of `map` (a box,
// clamped to the grid: nearBlocks with across = ceil(r / blockSize)); with `also` (the same
// grid), OR-ed with it.
Target dilateBlocks(const GpuScene& scene, const BlockMap& map, int across, int down, const BlockMap& also = {});
// The union of two maps of one grid.
Target uniteBlocks(const GpuScene& scene, const BlockMap& a, const BlockMap& b);
// The map of `factor`×`factorY` blocks of `map` (blocksOf: a block is set where any under it is;
// factorY < 0: `factor`).
Target poolBlocks(const GpuScene& scene, const BlockMap& map, int factor, int factorY = -1);
// ceil(radius / blockSize): how many blocks a reach of `radius` pixels spans (nearBlocks' d).
inline int blocksWithin(int radius, int blockSize) { return (radius + blockSize - 1) / blockSize; }

// One map of blockMaps: the blocks within (ax, ay) blocks of a set block of the source, OR within
// (bx, by) blocks of a set block of the finer map of one of the block's 2×2 children (then pooled);
// −1: no such term.
struct MapSpec {
  int ax = -1, ay = -1, bx = -1, by = -1;
};
// Every map of `specs` on `source`'s grid in one pass (blocks.frag STEP 3; 8 at most a pass, more
// in further passes): the returned targets' attachments, in order, 8 a target. `fine` (twice
// the grid; may be empty when no spec has a b term) is the finer map.
std::vector<Target> blockMaps(const GpuScene& scene, const BlockMap& source, const BlockMap& fine,
                              const std::vector<MapSpec>& specs);

}  // namespace mrr::gpu
