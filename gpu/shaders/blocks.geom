#version 330 core
// A block map's runs as rectangles (docs/port.md, "The GPU-resident frame"): for one row of the
// map and one segment of kBlockSegment blocks along it (common/shader_constants.h), each run of
// blocks equal to `blockValue` becomes one rectangle of the target, blockSize pixels a block,
// clipped to the target. A run that the row above holds too (the same ends, cut at the segment's
// ends) was drawn from there: the first row of a band draws it down to its last row, so a band
// along an edge is a few rectangles, as gpu/masks.cpp blockRects makes them on the host. Every
// pixel of a set block is covered once and no other.
layout(points) in;
layout(triangle_strip, max_vertices = 128) out;  // 2 kBlockSegment: a rectangle per two blocks at most
flat in ivec2 segmentRow[];
uniform sampler2D blockMap;  // R8: 1 where a block is set
uniform int blockValue;      // the runs of blocks equal to it: 1 (set) or 0 (clear)
uniform int blockSize;       // target pixels per block side
uniform vec2 targetSize;     // the target, pixels

bool matches(int x, int y) { return (texelFetch(blockMap, ivec2(x, y), 0).r > 0.5) == (blockValue != 0); }
// Row y holds the run [x0, x1) of the segment [s0, s1) exactly.
bool holdsRun(int x0, int x1, int y, int s0, int s1) {
  if (x0 > s0 && matches(x0 - 1, y)) return false;
  if (x1 < s1 && matches(x1, y)) return false;
  for (int x = x0; x < x1; ++x)
    if (!matches(x, y)) return false;
  return true;
}
void corner(vec2 p) {
  gl_Position = vec4(p / targetSize * 2.0 - 1.0, 0.0, 1.0);
  EmitVertex();
}
void main() {
  ivec2 grid = textureSize(blockMap, 0);
  int y = segmentRow[0].y;
  int s0 = segmentRow[0].x * kBlockSegment, s1 = min(s0 + kBlockSegment, grid.x);
  int x = s0;
  while (x < s1) {
    if (!matches(x, y)) {
      ++x;
      continue;
    }
    int x0 = x;
    while (x < s1 && matches(x, y)) ++x;
    if (y > 0 && holdsRun(x0, x, y - 1, s0, s1)) continue;  // drawn from the row above
    int y1 = y + 1;
    while (y1 < grid.y && holdsRun(x0, x, y1, s0, s1)) ++y1;
    vec2 lo = vec2(x0, y) * float(blockSize), hi = min(vec2(x, y1) * float(blockSize), targetSize);
    corner(lo);
    corner(vec2(hi.x, lo.y));
    corner(vec2(lo.x, hi.y));
    corner(hi);
    EndPrimitive();
  }
}
