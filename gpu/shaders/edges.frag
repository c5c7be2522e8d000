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
// pixel (normal and depth) tells the hit too, and the pass reads five texels, not ten.
bool isHit(ivec2 q) { return texelFetch(normalDepth, q, 0).w > 0.0; }
bool usable(ivec2 q, ivec2 size) { return inside(q, size) && isHit(q); }
float inverseDepth(ivec2 q) { return 1.0 / texelFetch(normalDepth, q, 0).w; }

// Relative second difference of d = 1/z along one axis: 0 on any plane.
float secondDifference(float dMinus, float d, float dPlus) { return abs(dMinus - 2.0 * d + dPlus) / d; }

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(normalDepth, 0);
  if (!isHit(p)) {  // background pixels carry no edge; their hit neighbours do
    edges = vec4(0.0);
#ifdef SHADOW_EDGES
    shadowEdge = vec4(0.0);
#endif
    return;
  }
  vec3 n = texelFetch(normalDepth, p, 0).xyz;
  ivec2 offsets[4] = ivec2[4](ivec2(-1, 0), ivec2(1, 0), ivec2(0, -1), ivec2(0, 1));
  // 1. normal edge: first derivative, max over the 4-neighbours inside the image.
  float normalMax = 0.0;
  bool backgroundNeighbour = false;
  for (int k = 0; k < 4; ++k) {
    ivec2 q = p + offsets[k];
    if (!inside(q, size)) continue;  // no edge comes from the border
    if (!isHit(q)) {
      backgroundNeighbour = true;  // 3. background edge
      continue;
    }
    normalMax = max(normalMax, 1.0 - dot(n, texelFetch(normalDepth, q, 0).xyz));
  }
  // 2. depth edge: second difference of 1/z, where both neighbours exist and are hits.
  float d = inverseDepth(p);
  float secondX = 0.0, secondY = 0.0;
  if (usable(p - ivec2(1, 0), size) && usable(p + ivec2(1, 0), size))
    secondX = secondDifference(inverseDepth(p - ivec2(1, 0)), d, inverseDepth(p + ivec2(1, 0)));
  if (usable(p - ivec2(0, 1), size) && usable(p + ivec2(0, 1), size))
    secondY = secondDifference(inverseDepth(p - ivec2(0, 1)), d, inverseDepth(p + ivec2(0, 1)));
  bool shadowDiffers = false;
#ifdef SHADOW_EDGES
  // 4. shadow edge: the one-tap shadow test differs from a hit 4-neighbour's
  bool lit = litAt(p);
  for (int k = 0; k < 4; ++k) {
    ivec2 q = p + offsets[k];
    if (usable(q, size) && litAt(q) != lit) shadowDiffers = true;
  }
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
