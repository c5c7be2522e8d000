#version 330 core
// Stage 2 — edge image E (SPEC §2), mirrors cpu_ref/edges.cpp: each kind kept apart. With
// SHADOW_EDGES (SSM) the shadow kind is on too, written to a second target. With E_ONLY (the
// GPU-resident frame, which needs no kinds) E alone goes to channel r of one 8-bit target.
// With EDGE_SAMPLE (cpu_ref/edges.cpp: edgeSample, SPEC §11): the never-slower rule's edge
// sample: E at the diagonal pixels of every 8×8 block, eight to a block side by side on a
// ⌈W/8⌉·8 × ⌈H/8⌉ R8 target; the host ORs each block's eight.
#include "edge_test.glsl"  // SPEC §2's test: normalDepth, the thresholds, shadowLit with SHADOW_EDGES
layout(location = 0) out vec4 edges;  // (normal, depth, background, E); EDGE_SAMPLE: (E, 0, 0, 1)
#if defined(SHADOW_EDGES) && !defined(EDGE_SAMPLE)
layout(location = 1) out vec4 shadowEdge;  // (shadow edge, 0, 0, 1)
#endif

void main() {
  ivec2 size = textureSize(normalDepth, 0);
#ifdef EDGE_SAMPLE
  // 1. fragment (x, y) of the ⌈W/8⌉·8 × ⌈H/8⌉ target is the diagonal pixel of block (x/8, y) in
  // column x: neighbouring fragments read neighbouring texels (one fragment per block, each
  // reading eight scattered diagonals, took twice as long on llvmpipe)
  const int step = kEdgeSampleStep;
  ivec2 f = ivec2(gl_FragCoord.xy);
  ivec2 q = ivec2(f.x, f.y * step + f.x % step);
  // 2. E there (every kind); 3., Ê as the OR of a block's eight, is the host's (gpu/edges.cpp)
  edges = vec4(inside(q, size) && anyKind(edgeAt(q, size)) ? 1.0 : 0.0, 0.0, 0.0, 1.0);
#else
  EdgeKinds kinds = edgeAt(ivec2(gl_FragCoord.xy), size);
#ifdef SHADOW_EDGES
  shadowEdge = vec4(float(kinds.shadow), 0.0, 0.0, 1.0);
#endif
#ifdef E_ONLY
  edges = vec4(float(anyKind(kinds)), 0.0, 0.0, 1.0);
#else
  edges = vec4(float(kinds.normal), float(kinds.depth), float(kinds.background), float(anyKind(kinds)));
#endif
#endif
}
