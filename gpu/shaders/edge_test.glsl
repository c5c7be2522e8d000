// SPEC §2's edge test at one pixel (cpu_ref/edges.cpp edgeAt), written once: edges.frag runs it at
// every pixel (or, EDGE_SAMPLE, at the edge sample's diagonal pixels), and rule.frag step 1 at
// each block's diagonal pixels for the never-slower rule's edge sample, whose texels lie in the
// rows that pass reads for its hit bits anyway.
uniform sampler2D normalDepth;  // G-buffer L0: view normal, depth (0 on a miss: the clear value)
uniform float normalThreshold;  // τ_n
uniform float depthThreshold;   // τ_z
#ifdef SHADOW_EDGES
uniform sampler2D shadowLit;    // the one-tap shadow test per pixel (shadowmap.frag, SHADOW_TEST)
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
