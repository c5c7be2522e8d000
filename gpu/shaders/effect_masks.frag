#version 330 core
// mrr-effect's masks (SPEC §12), mirrors cpu_ref/effect_masks.cpp. One pass per step, at the
// output's size; the host compiles a variant per pass shape (gpu/effect_masks.cpp):
//   STEP 1 effectFootprint, at full res (R32F): F(p) = scale · ρ(p) · f / z at an edge pixel
//     (E = 1) on geometry with z > 0, else 0; ρ = R (SSAO, SSGI) or, with EFFECT_SSM, the one-tap
//     penumbra bound (d_receiver − d_map) · 2 tan(θ/2) at a receiver facing the light
//   STEP 2 levelReach, then dilateByReach's pass along x (R32F): K(q) = min(cap, ⌊min(F_ℓ(q) / s_ℓ,
//     cap + 1) + ½⌋) where M_ℓ(q) = 1, else −1; H(x, y) = the largest K(q) of a q in row y with
//     |x − q_x| ≤ K(q), else −1
//   STEP 3 dilateByReach's pass along y (R8): M'(x, y) = [some y' has H(x, y') ≥ |y − y'|]
//   STEP 4 wideningOnly, the ablation's effect-only arm (SPEC §12.3, R8): M'_ℓ ∧ ¬M_ℓ
// Out of the level, nothing is read (no clamp, no wrap), as on the oracle.
layout(location = 0) out vec4 result;

#if STEP == 1
#include "shadowmap.glsl"
uniform sampler2D positionHit;  // level 0's G-buffer: view position, hit
uniform sampler2D normalDepth;  // level 0's G-buffer: view normal, depth
uniform sampler2D edges;        // E in channel EDGE_CHANNEL
uniform float reach;            // SSAO, SSGI: R, world units
uniform float tanHalfAngle;     // SSM: tan(θ/2) of the light's angular diameter
uniform float focal;            // View::focal, full-res pixels
uniform float scale;            // the footprint's multiplier k

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float footprint = 0.0;
  // 1. an edge pixel on geometry, in front of the camera (the G-buffer read at edge pixels alone)
  vec4 ph = vec4(0.0), nd = vec4(0.0);
  bool edge = texelFetch(edges, p, 0)[EDGE_CHANNEL] > 0.5;
  if (edge) {
    ph = texelFetch(positionHit, p, 0);
    nd = texelFetch(normalDepth, p, 0);
  }
  float z = nd.w;
  if (edge && ph.w > 0.5 && z > 0.0) {
    // 2. the effect's reach on the receiver, world units
    float rho = 0.0;
#if EFFECT_SSM
    Receiver r = receiverAt(viewToWorld(ph.xyz), viewDirectionToWorld(nd.xyz));
    if (r.facesLight) {
      float blocker = depthAt(r.u, r.v);
      if (blocker < r.depth) rho = (r.depth - blocker) * 2.0 * tanHalfAngle;
    }
#else
    rho = reach;
#endif
    // 3. projected at the pixel's depth, full-res pixels
    footprint = scale * (rho * focal / z);
  }
  result = vec4(footprint, 0.0, 0.0, 1.0);
}

#elif STEP == 4
uniform sampler2D source;    // M'_ℓ, the widened mask
uniform sampler2D geometry;  // M_ℓ in channel MASK_CHANNEL

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  // 1. the pixels the widening adds: M'_ℓ ∧ ¬M_ℓ
  bool widened = texelFetch(source, p, 0).r > 0.5;
  bool edge = texelFetch(geometry, p, 0)[MASK_CHANNEL] > 0.5;
  result = vec4(widened && !edge ? 1.0 : 0.0, 0.0, 0.0, 1.0);
}

#else
uniform sampler2D source;  // step 2: M_ℓ (channel MASK_CHANNEL); step 3: H
#if STEP == 2
uniform sampler2D footprint;  // F_ℓ: the max of F over each level pixel's block
uniform float levelScale;     // s_ℓ = 2^ℓ

// levelReach: K(q) in level pixels, −1 where M_ℓ(q) = 0
int reachAt(ivec2 q) {
  if (texelFetch(source, q, 0)[MASK_CHANNEL] < 0.5) return -1;
  float levelPixels = min(texelFetch(footprint, q, 0).r / levelScale, float(CAP) + 1.0);  // s = 2^ℓ: exact
  return min(CAP, int(floor(levelPixels + 0.5)));
}
#endif

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(source, 0);
#if STEP == 2
  // 1. along x: the widest reach of a q in this row that reaches p
  int across = -1;
  for (int d = -CAP; d <= CAP; ++d) {
    int x = p.x + d;
    if (x < 0 || x >= size.x) continue;
    int k = reachAt(ivec2(x, p.y));
    if (k >= abs(d)) across = max(across, k);
  }
  result = vec4(float(across), 0.0, 0.0, 1.0);
#else
  // 2. along y: some row y' whose H reaches |y − y'|
  float widened = 0.0;
  for (int d = -CAP; d <= CAP; ++d) {
    int y = p.y + d;
    if (y < 0 || y >= size.y) continue;
    if (texelFetch(source, ivec2(p.x, y), 0).r >= float(abs(d))) widened = 1.0;
  }
  result = vec4(widened, 0.0, 0.0, 1.0);
#endif
}
#endif
