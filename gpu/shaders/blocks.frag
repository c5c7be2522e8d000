#version 330 core
// Block maps (docs/port.md, "The GPU-resident frame"): R8 images on a grid of blocks, 1 where a
// block may hold a pass's work, made on the GPU from the masks and drawn over by blocks.geom.
// The host's equivalents are common/frame.h nearBlocks and gpu/masks.cpp blocksOf. One pass per
// step, at the output grid's size; the host compiles a variant per shape:
//   STEP 1 dilate: 1 where a block of `source` within DX blocks across and DY down is set (a
//     box, clamped to the grid: nearBlocks with d = ceil(r / blockSize)); with UNITE, OR `also`
//   STEP 2 pool: 1 where any of the FACTOR_X×FACTOR_Y blocks of `source` under it is set
//     (blocksOf; the last row and column of blocks may be partial)
uniform sampler2D source;  // a block map
#if UNITE
uniform sampler2D also;    // step 1: a block map of the output's grid, OR-ed in
#endif
layout(location = 0) out vec4 result;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(source, 0) - 1;
  float set = 0.0;
#if STEP == 1
  for (int j = -DY; j <= DY; ++j)
    for (int i = -DX; i <= DX; ++i) set = max(set, texelFetch(source, clamp(p + ivec2(i, j), ivec2(0), last), 0).r);
#if UNITE
  set = max(set, texelFetch(also, p, 0).r);
#endif
#else
  for (int j = 0; j < FACTOR_Y; ++j)
    for (int i = 0; i < FACTOR_X; ++i)
      set = max(set, texelFetch(source, min(p * ivec2(FACTOR_X, FACTOR_Y) + ivec2(i, j), last), 0).r);
#endif
  result = vec4(set > 0.5 ? 1.0 : 0.0, 0.0, 0.0, 1.0);
}
