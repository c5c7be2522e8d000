#version 330 core
// Block maps (docs/port.md, "The GPU-resident frame"): R8 images on a grid of blocks, 1 where a
// block may hold a pass's work, made on the GPU from E's own pyramid and drawn over by
// blocks.geom. The host's equivalents are common/frame.h nearBlocks and gpu/masks.cpp blocksOf.
// One pass per step, at the output grid's size; the host compiles a variant per shape:
//   STEP 1 dilate: 1 where a block of `source` within DX blocks across and DY down is set (a
//     box, clamped to the grid: nearBlocks with d = ceil(r / blockSize)); with UNITE, OR `also`
//   STEP 2 pool: 1 where any of the FACTOR_X×FACTOR_Y blocks of `source` under it is set
//     (blocksOf; the last row and column of blocks may be partial)
//   STEP 3 maps: OUTPUTS maps of one grid at once (gpu/masks.cpp draws every cover of a frame's
//     masks from two of these passes). Map k (SPEC_k = (ax, ay, bx, by), −1: no term) is 1 where
//     a set block of `source` (this grid) lies within ax blocks across and ay down, or, with FINE,
//     a set block of `fine` (the grid twice as fine) within bx across and by down of one of the
//     block's 2×2 children: nearBlocks of `source`, OR blocksOf(nearBlocks of `fine`, 2). A union
//     of boxes about one block is the largest box, so a dilation of a dilation, and the masks'
//     closure of several levels' supports, are one term each.
//   STEP 4 pack: bit k of component c of output texel (i, y) is 1 where block (i kBlockSegment +
//     32 c + k, y) of `source` is set: a row's segments as four words each, which blocks.geom reads
//     (GpuScene::draw packs a map before each pass drawn over its runs)
uniform sampler2D source;  // a block map
#if STEP == 1 && UNITE
uniform sampler2D also;    // step 1: a block map of the output's grid, OR-ed in
#endif
#if STEP == 3 && FINE
uniform sampler2D fine;    // step 3: the map of the grid twice as fine
#endif
#if STEP == 4
layout(location = 0) out uvec4 packedBits;
#else
layout(location = 0) out vec4 result;
#endif
#if STEP == 3
#if OUTPUTS > 1
layout(location = 1) out vec4 map1;
#endif
#if OUTPUTS > 2
layout(location = 2) out vec4 map2;
#endif
#if OUTPUTS > 3
layout(location = 3) out vec4 map3;
#endif
#if OUTPUTS > 4
layout(location = 4) out vec4 map4;
#endif
#if OUTPUTS > 5
layout(location = 5) out vec4 map5;
#endif
#if OUTPUTS > 6
layout(location = 6) out vec4 map6;
#endif
#if OUTPUTS > 7
layout(location = 7) out vec4 map7;
#endif
vec4 bit(uint set, int k) { return vec4((set >> uint(k)) & 1u, 0.0, 0.0, 1.0); }
#endif

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
  result = vec4(set > 0.5 ? 1.0 : 0.0, 0.0, 0.0, 1.0);
#elif STEP == 2
  for (int j = 0; j < FACTOR_Y; ++j)
    for (int i = 0; i < FACTOR_X; ++i)
      set = max(set, texelFetch(source, min(p * ivec2(FACTOR_X, FACTOR_Y) + ivec2(i, j), last), 0).r);
  result = vec4(set > 0.5 ? 1.0 : 0.0, 0.0, 0.0, 1.0);
#elif STEP == 4
  uvec4 bits = uvec4(0u);
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 32; ++k) {
      int x = p.x * kBlockSegment + 32 * c + k;
      if (x <= last.x && texelFetch(source, ivec2(x, p.y), 0).r > 0.5) bits[c] |= 1u << uint(k);
    }
  packedBits = bits;
#else
  // one scan of each window, every map's box tested against each set block found
  const ivec4 kSpecs[8] = ivec4[8](SPEC_0, SPEC_1, SPEC_2, SPEC_3, SPEC_4, SPEC_5, SPEC_6, SPEC_7);
  uint maps = 0u;
  for (int j = -REACH_A; j <= REACH_A; ++j)
    for (int i = -REACH_A; i <= REACH_A; ++i) {
      ivec2 q = p + ivec2(i, j);
      if (any(lessThan(q, ivec2(0))) || any(greaterThan(q, last)) || texelFetch(source, q, 0).r < 0.5) continue;
      for (int k = 0; k < OUTPUTS; ++k)
        if (kSpecs[k].x >= 0 && abs(i) <= kSpecs[k].x && abs(j) <= kSpecs[k].y) maps |= 1u << uint(k);
    }
#if FINE
  ivec2 fineLast = textureSize(fine, 0) - 1;
  for (int j = -REACH_B; j <= 1 + REACH_B; ++j)
    for (int i = -REACH_B; i <= 1 + REACH_B; ++i) {
      ivec2 q = 2 * p + ivec2(i, j);  // within b of a child 2p + (0 or 1)
      if (any(lessThan(q, ivec2(0))) || any(greaterThan(q, fineLast)) || texelFetch(fine, q, 0).r < 0.5) continue;
      int dx = i < 0 ? -i : max(i - 1, 0), dy = j < 0 ? -j : max(j - 1, 0);
      for (int k = 0; k < OUTPUTS; ++k)
        if (kSpecs[k].z >= 0 && dx <= kSpecs[k].z && dy <= kSpecs[k].w) maps |= 1u << uint(k);
    }
#endif
  result = bit(maps, 0);
#if OUTPUTS > 1
  map1 = bit(maps, 1);
#endif
#if OUTPUTS > 2
  map2 = bit(maps, 2);
#endif
#if OUTPUTS > 3
  map3 = bit(maps, 3);
#endif
#if OUTPUTS > 4
  map4 = bit(maps, 4);
#endif
#if OUTPUTS > 5
  map5 = bit(maps, 5);
#endif
#if OUTPUTS > 6
  map6 = bit(maps, 6);
#endif
#if OUTPUTS > 7
  map7 = bit(maps, 7);
#endif
#endif
}
