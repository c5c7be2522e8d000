#version 330 core
// Stage 2 — edge image E (SPEC §2), mirrors cpu_ref/edges.cpp: each kind kept apart. With
// SHADOW_EDGES (SSM) the shadow kind is on too, written to a second target. With E_ONLY (the
// GPU-resident frame, which needs no kinds) E alone goes to channel r of one 8-bit target.
uniform sampler2D normalDepth;  // G-buffer L0: view normal, depth (0 on a miss: the clear value)
uniform float normalThreshold;  // τ_n
uniform float depthThreshold;   // τ_z
layout(location = 0) out vec4 edges;  // (normal, depth, background, E)
#ifdef SHADOW_EDGES
uniform sampler2D shadowLit;    // the one-tap shadow test per pixel (shadowmap.frag, SHADOW_TEST)
layout(location = 1) out vec4 shadowEdge;  // (shadow edge, 0, 0, 1)
bool litAt(ivec2 q) { return texelFetch(shadowLit, q, 0).r > 0.5; }
#endif

bool inside(ivec2 q, ivec2 size) { return all(greaterThanEqual(q, ivec2(0))) && all(lessThan(q, size)); }
// A hit lies in front of the camera (depth > 0); a miss keeps the cleared 0. So one texel per
// pixel (normal and depth) tells the hit too: the pass reads five texels, each once.
bool isHit(vec4 normalDepthTexel) { return normalDepthTexel.w > 0.0; }

// Relative second difference of d = 1/z along one axis: 0 on any plane.
float secondDifference(float dMinus, float d, float dPlus) { return abs(dMinus - 2.0 * d + dPlus) / d; }

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(normalDepth, 0);
  vec4 centre = texelFetch(normalDepth, p, 0);
  if (!isHit(centre)) {  // background pixels carry no edge; their hit neighbours do
    edges = vec4(0.0);
#ifdef SHADOW_EDGES
    shadowEdge = vec4(0.0);
#endif
    return;
  }
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
  bool shadowDiffers = false;
#ifdef SHADOW_EDGES
  // 4. shadow edge: the one-tap shadow test differs from a hit 4-neighbour's
  bool lit = litAt(p);
  for (int k = 0; k < 4; ++k)
    if (usable[k] && litAt(p + offsets[k]) != lit) shadowDiffers = true;
  shadowEdge = vec4(float(shadowDiffers), 0.0, 0.0, 1.0);
#endif
  bool normalEdge = normalMax > normalThreshold;
  bool depthEdge = max(secondX, secondY) > depthThreshold;
  // 5. E = OR of the kinds
  bool e = normalEdge || depthEdge || backgroundNeighbour || shadowDiffers;
#ifdef E_ONLY
  edges = vec4(float(e), 0.0, 0.0, 1.0);
#else
  edges = vec4(float(normalEdge), float(depthEdge), float(backgroundNeighbour), float(e));
#endif
}
