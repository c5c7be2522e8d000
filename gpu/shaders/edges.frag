#version 330 core
// Stage 2 — edge image E (SPEC §2), mirrors cpu_ref/edges.cpp: each kind kept apart. With
// SHADOW_EDGES (SSM) the shadow kind is on too, written to a second target. With E_ONLY (the
// GPU-resident frame, which needs no kinds) E alone goes to channel r of one 8-bit target.
// With EDGE_SAMPLE (cpu_ref/edges.cpp: edgeSample, SPEC §11): the never-slower rule's edge
// sample: E at the diagonal pixels of every 8×8 block, eight to a block side by side on a
// ⌈W/8⌉·8 × ⌈H/8⌉ R8 target; the host ORs each block's eight.
uniform sampler2D normalDepth;  // G-buffer L0: view normal, depth (0 on a miss: the clear value)
uniform float normalThreshold;  // τ_n
uniform float depthThreshold;   // τ_z
layout(location = 0) out vec4 edges;  // (normal, depth, background, E); EDGE_SAMPLE: (E, 0, 0, 1)
#ifdef SHADOW_EDGES
uniform sampler2D shadowLit;    // the one-tap shadow test per pixel (shadowmap.frag, SHADOW_TEST)
#ifndef EDGE_SAMPLE
layout(location = 1) out vec4 shadowEdge;  // (shadow edge, 0, 0, 1)
#endif
bool litAt(ivec2 q) { return texelFetch(shadowLit, q, 0).r > 0.5; }
#endif

bool inside(ivec2 q, ivec2 size) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)); }
// A hit lies in front of the camera (depth > 0); a miss keeps the cleared 0. So one texel per
// pixel (normal and depth) tells the hit too: the pass reads five texels, each once.
bool isHit(vec4 normalDepthTexel) { return normalDepthTexel.w > 0.0; }

// Relative second difference of d = 1/z along one axis: 0 on any plane.
float secondDifference(float dMinus, float d, float dPlus) { return abs(dMinus - 2.0 * d + dPlus) / d; }

struct EdgeKinds {
  bool normal, depth, background, shadow;
};

// SPEC §2 at pixel p (cpu_ref/edges.cpp: edgeAt): every kind, all false off geometry.
EdgeKinds edgeAt(ivec2 p, ivec2 size) {
  EdgeKinds kinds = EdgeKinds(false, false, false, false);
  vec4 centre = texelFetch(normalDepth, p, 0);
  if (!isHit(centre)) return kinds;  // background pixels carry no edge; their hit neighbours do
  vec3 n = centre.xyz;
  // the 4-neighbours (x−1, x+1, y−1, y+1), read once; `usable`: inside the image and a hit
  ivec2 offsets[4] = ivec2[4](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
  vec4 neighbour[4];
  bool within[4], usable[4];
  for (int k = 0; k < 4; ++k) {
    ivec2 q = p + offsets[k];
    within[k] = inside(q, size);
    neighbour[k] = texelFetch(normalDepth, clamp(q, ivec2(0), size - 1), 0);
    usable[k] = within[k] && isHit(neighbour[k]);
  }
  // 1. normal edge: first derivative, max over the 4-neighbours inside the image.
  float normalMax = 0.0;
  bool backgroundNeighbour = false;
  for (int k = 0; k < 4; ++k) {
    if (!within[k]) continue;  // no edge comes from the border
    if (!usable[k]) {
      backgroundNeighbour = true;  // 3. background edge
      continue;
    }
    normalMax = max(normalMax, 1.0 - dot(n, neighbour[k].xyz));
  }
  // 2. depth edge: second difference of 1/z, where both neighbours exist and are hits.
  float d = 1.0 / centre.w;
  float secondX = 0.0, secondY = 0.0;
  if (usable[0] && usable[1]) secondX = secondDifference(1.0 / neighbour[0].w, d, 1.0 / neighbour[1].w);
  if (usable[2] && usable[3]) secondY = secondDifference(1.0 / neighbour[2].w, d, 1.0 / neighbour[3].w);
#ifdef SHADOW_EDGES
  // 4. shadow edge: the one-tap shadow test differs from a hit 4-neighbour's
  bool lit = litAt(p);
  for (int k = 0; k < 4; ++k)
    if (usable[k] && litAt(p + offsets[k]) != lit) kinds.shadow = true;
#endif
  kinds.normal = normalMax > normalThreshold;
  kinds.depth = max(secondX, secondY) > depthThreshold;
  kinds.background = backgroundNeighbour;
  return kinds;
}

// 5. E = OR of the kinds
bool anyKind(EdgeKinds k) { return k.normal || k.depth || k.background || k.shadow; }

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
