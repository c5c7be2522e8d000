#version 330 core
// A block map's runs as rectangles (docs/port.md, "The GPU-resident frame"): for one row of the
// map and one segment of kBlockSegment blocks along it (common/shader_constants.h), each run of
// blocks equal to `blockValue` becomes one rectangle of the target, blockSize pixels a block,
// clipped to the target. A run that the row above holds too (the same ends, cut at the segment's
// ends) was drawn from there: the first row of a band draws it down to its last row, so a band
// along an edge is a few rectangles, as gpu/masks.cpp blockRects makes them on the host. Every
// pixel of a set block is covered once and no other. The map comes packed (blocks.frag STEP 4):
// a segment of a row is one texel of four words, so a run and the test of a row below are a few
// bit operations and one fetch, not a fetch a block (on llvmpipe this shader runs on one host thread).
layout(points) in;
layout(triangle_strip, max_vertices = 256) out;  // 2 kBlockSegment: a rectangle per two blocks at most
flat in ivec2 segmentRow[];
uniform usampler2D blockBits;  // blocks.frag STEP 4: bit k of component c of texel (i, y) = block (i kBlockSegment + 32 c + k, y) set
uniform ivec2 blockGrid;       // the map's size in blocks
uniform int blockValue;        // the runs of blocks equal to it: 1 (set) or 0 (clear)
uniform int blockSize;         // target pixels per block side
uniform vec2 targetSize;       // the target, pixels

uvec4 inSegment;  // the segment's blocks inside the grid, as bits (main)
// The blocks of row y in this segment equal to blockValue, bit k of word c = block s0 + 32 c + k.
uvec4 rowBits(int y) {
  uvec4 bits = texelFetch(blockBits, ivec2(segmentRow[0].x, y), 0);
  return (blockValue != 0 ? bits : ~bits) & inSegment;
}
// Word `bits` holds `run` exactly: all of it, and neither block beside it inside the word.
bool holdsRun(uint bits, uint run) {
  uint beside = ((run << 1) | (run >> 1)) & ~run;
  return (bits & run) == run && (bits & beside) == 0u;
}
int lowestBit(uint v) {  // v != 0 (GLSL 3.30 has no findLSB)
  int n = 0;
  if ((v & 0xFFFFu) == 0u) { n += 16; v >>= 16; }
  if ((v & 0xFFu) == 0u) { n += 8; v >>= 8; }
  if ((v & 0xFu) == 0u) { n += 4; v >>= 4; }
  if ((v & 0x3u) == 0u) { n += 2; v >>= 2; }
  if ((v & 0x1u) == 0u) n += 1;
  return n;
}
int ones(uint v) {  // the set bits of v (GLSL 3.30 has no bitCount)
  v = v - ((v >> 1) & 0x55555555u);
  v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
  return int((((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24);
}
void corner(vec2 p) {
  gl_Position = vec4(p / targetSize * 2.0 - 1.0, 0.0, 1.0);
  EmitVertex();
}
void main() {
  int y = segmentRow[0].y, s0 = segmentRow[0].x * kBlockSegment;
  for (int c = 0; c < 4; ++c) {
    int count = clamp(blockGrid.x - (s0 + 32 * c), 0, 32);
    inSegment[c] = count == 32 ? 0xFFFFFFFFu : (1u << uint(count)) - 1u;
  }
  uvec4 row = rowBits(y), above = y > 0 ? rowBits(y - 1) : uvec4(0u);
  for (int c = 0; c < 4; ++c) {
    uint left = row[c];
    while (left != 0u) {
      uint run = left & ~(left + (left & (~left + 1u)));  // the lowest run of set bits
      left &= ~run;
      if (holdsRun(above[c], run)) continue;  // drawn from the row above
      int y1 = y + 1;
      while (y1 < blockGrid.y && holdsRun(rowBits(y1)[c], run)) ++y1;
      int x0 = s0 + 32 * c + lowestBit(run);
      vec2 lo = vec2(x0, y) * float(blockSize), hi = min(vec2(x0 + ones(run), y1) * float(blockSize), targetSize);
      corner(lo);
      corner(vec2(hi.x, lo.y));
      corner(vec2(lo.x, hi.y));
      corner(hi);
      EndPrimitive();
    }
  }
}
