#version 330 core
// Sums of counts on the GPU (gpu/counts.cpp): a pass writes a few counts per block into RGBA32UI
// targets (rule.frag); these passes add them up, so the host reads a few integers instead of an
// image (docs/port.md, "What a frame costs the host"). One pass per step:
//   STEP 1 reduce: each of the TARGETS outputs (up to 8, inputs of one size) sums a FACTOR×FACTOR
//     tile of its input (texels past the input's edge count 0)
//   STEP 2 gather: fragment k of a SOURCES×1 row sums the whole of input k (at most 16×16 texels)
#if STEP == 1
uniform usampler2D values0;
layout(location = 0) out uvec4 sum0;
#if TARGETS > 1
uniform usampler2D values1;
layout(location = 1) out uvec4 sum1;
#endif
#if TARGETS > 2
uniform usampler2D values2;
layout(location = 2) out uvec4 sum2;
#endif
#if TARGETS > 3
uniform usampler2D values3;
layout(location = 3) out uvec4 sum3;
#endif
#if TARGETS > 4
uniform usampler2D values4;
layout(location = 4) out uvec4 sum4;
#endif
#if TARGETS > 5
uniform usampler2D values5;
layout(location = 5) out uvec4 sum5;
#endif
#if TARGETS > 6
uniform usampler2D values6;
layout(location = 6) out uvec4 sum6;
#endif
#if TARGETS > 7
uniform usampler2D values7;
layout(location = 7) out uvec4 sum7;
#endif

uvec4 tile(usampler2D values, ivec2 p) {
  ivec2 size = textureSize(values, 0), lo = p * FACTOR, hi = min(lo + FACTOR, size);
  uvec4 s = uvec4(0u);
  for (int y = lo.y; y < hi.y; ++y)
    for (int x = lo.x; x < hi.x; ++x) s += texelFetch(values, ivec2(x, y), 0);
  return s;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  sum0 = tile(values0, p);
#if TARGETS > 1
  sum1 = tile(values1, p);
#endif
#if TARGETS > 2
  sum2 = tile(values2, p);
#endif
#if TARGETS > 3
  sum3 = tile(values3, p);
#endif
#if TARGETS > 4
  sum4 = tile(values4, p);
#endif
#if TARGETS > 5
  sum5 = tile(values5, p);
#endif
#if TARGETS > 6
  sum6 = tile(values6, p);
#endif
#if TARGETS > 7
  sum7 = tile(values7, p);
#endif
}
#else
uniform usampler2D source0;
#if SOURCES > 1
uniform usampler2D source1;
#endif
#if SOURCES > 2
uniform usampler2D source2;
#endif
#if SOURCES > 3
uniform usampler2D source3;
#endif
#if SOURCES > 4
uniform usampler2D source4;
#endif
#if SOURCES > 5
uniform usampler2D source5;
#endif
#if SOURCES > 6
uniform usampler2D source6;
#endif
#if SOURCES > 7
uniform usampler2D source7;
#endif
layout(location = 0) out uvec4 sum;

uvec4 total(usampler2D values) {
  ivec2 size = textureSize(values, 0);
  uvec4 s = uvec4(0u);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x) s += texelFetch(values, ivec2(x, y), 0);
  return s;
}

void main() {
  int k = int(gl_FragCoord.x);
  uvec4 s = uvec4(0u);
  if (k == 0) s = total(source0);
#if SOURCES > 1
  else if (k == 1) s = total(source1);
#endif
#if SOURCES > 2
  else if (k == 2) s = total(source2);
#endif
#if SOURCES > 3
  else if (k == 3) s = total(source3);
#endif
#if SOURCES > 4
  else if (k == 4) s = total(source4);
#endif
#if SOURCES > 5
  else if (k == 5) s = total(source5);
#endif
#if SOURCES > 6
  else if (k == 6) s = total(source6);
#endif
#if SOURCES > 7
  else if (k == 7) s = total(source7);
#endif
  sum = s;
}
#endif
