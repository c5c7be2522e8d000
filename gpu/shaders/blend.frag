#version 330 core
// Stage 5 — masked-bilinear upsampling and the blend (SPEC §5, the corrected Eq. 1), mirrors
// cpu_ref/blend.cpp. Two variants of one file:
//   (default)   one full-res pass per enabled level, coarse to fine; it writes ĉ_ℓ, α_ℓ,
//               c'_ℓ = α ĉ_ℓ + (1 − α) c'_coarser and the level map (--stages, probe, compare)
//   FINAL_ONLY  one full-res pass for every level at once: the final image and level map,
//               bit-identical to the per-level passes (as cpu_ref's blendFinalOnly): α fine to
//               coarse up to the first α = 1 (nothing below it shows: blendStep(1, f, c) = f),
//               then the same steps coarse to fine in registers, a level's colour read only
//               where its α > 0 (blendStep(0, f, c) = c), its stencil only where â > 0. The host
//               compiles one variant per set of finer levels (FINE_LEVELS, a bit per level
//               0–2), so no sampler is chosen at run time, and draws the variant without
//               finer levels over the blocks where no finer α can be > 0 (gpu/blend.cpp).
//   REACH       SPEC §12.5 step 1 (mrr-effect's trim), before any level is shaded: R(p), the
//               coarsest level the blend reads at p, from the levels' S and a alone: FINAL_ONLY's
//               α fine to coarse up to the first α = 1 (else the coarsest), ℓ/255 in an R8
//               target on the padded grid, 0 outside W×H (cpu_ref/blend.cpp blendReach).

// 1. u = (p − ⌊s/2⌋)/s for full-res pixel p on a level of scale s (level pixel x holds full-res
// pixel x·s + ⌊s/2⌋, SPEC §0): tap k's texel (clamped to the level grid) and bilinear weight b.
void bilinearTap(int k, ivec2 p, int scale, ivec2 last, out ivec2 q, out float b) {
  vec2 u = vec2(p - scale / 2) / float(scale);
  vec2 f = floor(u);
  vec2 t = u - f;
  ivec2 o = ivec2(k & 1, k >> 1);
  q = clamp(ivec2(f) + o, ivec2(0), last);
  b = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
}

// 2. Over the four taps: â = Σ b a (all taps; with `wantAlpha`), the coverage Σ b over the
// rendered taps (S = 1) and their colour Σ b c (masked bilinear: an unrendered tap is never read).
void upsample(sampler2D sub, sampler2D stencilMask, sampler2D alphaMask, int scale, ivec2 p, bool wantAlpha,
              out vec3 color, out float coverage, out float alphaHat) {
  ivec2 last = textureSize(stencilMask, 0) - 1;
  color = vec3(0.0);
  coverage = 0.0;
  alphaHat = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 q;
    float b;
    bilinearTap(k, p, scale, last, q, b);
    // â = Σ b_q a(q), over all taps
    if (wantAlpha) alphaHat += b * texelFetch(alphaMask, q, 0).r;
    // masked bilinear: only rendered taps (S = 1) carry colour
    if (texelFetch(stencilMask, q, 0).r < 0.5) continue;
    coverage += b;
    color += b * texelFetch(sub, q, 0).rgb;
  }
}

// 3. α = min(â·w, 1) where some tap is rendered, else 0.
float blendAlpha(float coverage, float alphaHat, float weight) {
  float alpha = 0.0;
  if (coverage > 0.0) alpha = min(alphaHat * weight, 1.0);
  return alpha;
}

#if defined(FINAL_ONLY) || defined(REACH)
// â = Σ b a over a finer level's four taps, in upsample's order.
float alphaHatAt(sampler2D alphaMask, int scale, ivec2 p) {
  ivec2 last = textureSize(alphaMask, 0) - 1;
  float alphaHat = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 q;
    float b;
    bilinearTap(k, p, scale, last, q, b);
    alphaHat += b * texelFetch(alphaMask, q, 0).r;
  }
  return alphaHat;
}
#endif

#ifdef REACH
// α_ℓ of a finer level alone: levelSample's α, the same sums without the colour.
float levelAlpha(sampler2D stencilMask, sampler2D alphaMask, int scale, float weight, ivec2 p) {
  float alphaHat = alphaHatAt(alphaMask, scale, p);
  if (alphaHat == 0.0) return 0.0;
  ivec2 last = textureSize(stencilMask, 0) - 1;
  float coverage = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 q;
    float b;
    bilinearTap(k, p, scale, last, q, b);
    if (texelFetch(stencilMask, q, 0).r >= 0.5) coverage += b;
  }
  return blendAlpha(coverage, alphaHat, weight);
}
// ... and at level 0, levelZeroSample's: its own texel (s = 1)
float levelZeroAlpha(sampler2D stencilMask, sampler2D alphaMask, float weight, ivec2 p) {
  float alphaHat = texelFetch(alphaMask, p, 0).r;
  if (alphaHat == 0.0) return 0.0;
  return blendAlpha(texelFetch(stencilMask, p, 0).r < 0.5 ? 0.0 : 1.0, alphaHat, weight);
}
#endif

#ifdef FINAL_ONLY
// α_ℓ and ĉ_ℓ of a finer level in one sweep of its taps, with upsample's sums in upsample's
// order: â first (four reads), and only where â > 0 (else α = 0 whatever the coverage) the
// stencil and the colour of the rendered taps.
float levelSample(sampler2D sub, sampler2D stencilMask, sampler2D alphaMask, int scale, float weight, ivec2 p,
                  out vec3 color) {
  ivec2 last = textureSize(stencilMask, 0) - 1;
  float alphaHat = alphaHatAt(alphaMask, scale, p), coverage = 0.0;
  color = vec3(0.0);
  if (alphaHat == 0.0) return 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 q;
    float b;
    bilinearTap(k, p, scale, last, q, b);
    if (texelFetch(stencilMask, q, 0).r < 0.5) continue;
    coverage += b;
    color += b * texelFetch(sub, q, 0).rgb;
  }
  if (coverage > 0.0) color /= coverage;
  return blendAlpha(coverage, alphaHat, weight);
}

// levelSample at level 0, as its own function: with s = 1, u = p, so tap 0 is p itself with
// b = 1 and taps 1–3 have b = 0. Each of levelSample's sums is then level 0's own texel (x + 0·y
// = x for the finite values the levels hold), bit for bit, and the three zero-weight taps are
// not read: 3 reads a pixel instead of up to 12.
float levelZeroSample(sampler2D sub, sampler2D stencilMask, sampler2D alphaMask, float weight, ivec2 p,
                      out vec3 color) {
  float alphaHat = texelFetch(alphaMask, p, 0).r;
  color = vec3(0.0);
  if (alphaHat == 0.0) return 0.0;
  float coverage = texelFetch(stencilMask, p, 0).r < 0.5 ? 0.0 : 1.0;
  if (coverage > 0.0) color = texelFetch(sub, p, 0).rgb;
  return blendAlpha(coverage, alphaHat, weight);
}

// ĉ_C of the coarsest enabled level, whose S is 1 on its whole grid where the host says so
// (COARSEST_COVERED: masks drawn by drawMasks), so its stencil is not read: the same sums.
vec3 coarsestSample(sampler2D sub, sampler2D stencilMask, int scale, ivec2 p) {
  ivec2 last = textureSize(stencilMask, 0) - 1;
  float coverage = 0.0;
  vec3 color = vec3(0.0);
  for (int k = 0; k < 4; ++k) {
    ivec2 q;
    float b;
    bilinearTap(k, p, scale, last, q, b);
#ifndef COARSEST_COVERED
    if (texelFetch(stencilMask, q, 0).r < 0.5) continue;
#endif
    coverage += b;
    color += b * texelFetch(sub, q, 0).rgb;
  }
  return coverage > 0.0 ? color / coverage : vec3(0.0);
}
#endif

#ifdef REACH
uniform sampler2D stencil0, stencil1, stencil2;  // S_ℓ and a_ℓ of the finer levels (those in FINE_LEVELS)
uniform sampler2D alpha0, alpha1, alpha2;
uniform float weights[3];  // w_ℓ of the finer levels
uniform ivec2 frame;       // W×H
// COARSEST_LEVEL: C (defined by the host, gpu/blend.cpp drawBlendReach)
layout(location = 0) out vec4 reachOut;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  int reach = COARSEST_LEVEL;
  if (p.x >= frame.x || p.y >= frame.y) {
    reach = 0;  // outside W×H, which the blend never draws
  } else {
    bool opaque = false;
#if (FINE_LEVELS & 1) != 0
    opaque = levelZeroAlpha(stencil0, alpha0, weights[0], p) == 1.0;
    if (opaque) reach = 0;
#endif
#if (FINE_LEVELS & 2) != 0
    if (!opaque) {
      opaque = levelAlpha(stencil1, alpha1, 2, weights[1], p) == 1.0;
      if (opaque) reach = 1;
    }
#endif
#if (FINE_LEVELS & 4) != 0
    if (!opaque) {
      opaque = levelAlpha(stencil2, alpha2, 4, weights[2], p) == 1.0;
      if (opaque) reach = 2;
    }
#endif
  }
  reachOut = vec4(float(reach) / 255.0, 0.0, 0.0, 1.0);
}
#elif !defined(FINAL_ONLY)
uniform sampler2D sub;          // c_ℓ at level resolution (rgb)
uniform sampler2D stencilMask;  // S_ℓ
uniform sampler2D alphaMask;    // a_ℓ
uniform sampler2D coarser;      // c'_{next coarser enabled} at full res (unused at the coarsest)
uniform sampler2D coarserLevel; // its level map, ℓ/255 in an R8 target (unused at the coarsest)
uniform bool coarsest;
uniform int level;              // ℓ
uniform int scale;              // s_ℓ
uniform float weight;           // w_ℓ
layout(location = 0) out vec4 cHat;
layout(location = 1) out vec4 alphaOut;
layout(location = 2) out vec4 composite;
layout(location = 3) out vec4 levelMap;  // the finest level so far with α > 0 (ℓ/255)

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 color;
  float coverage, alphaHat;
  upsample(sub, stencilMask, alphaMask, scale, p, true, color, coverage, alphaHat);
  if (coverage > 0.0) color /= coverage;
  float alpha = coarsest ? (coverage > 0.0 ? 1.0 : 0.0) : blendAlpha(coverage, alphaHat, weight);
  vec3 below = coarsest ? vec3(0.0) : texelFetch(coarser, p, 0).rgb;
  // 4. c'_ℓ = α ĉ_ℓ + (1 − α) c'_coarser (written out, not mix(), to keep the host's order)
  vec3 result = coarsest ? color : alpha * color + (1.0 - alpha) * below;
  cHat = vec4(color, 1.0);
  alphaOut = vec4(alpha, 0.0, 0.0, 1.0);
  composite = vec4(result, 1.0);
  // 5. the level map: the coarsest level everywhere, then each finer level where α > 0
  float from = coarsest || alpha > 0.0 ? float(level) / 255.0 : texelFetch(coarserLevel, p, 0).r;
  levelMap = vec4(from, 0.0, 0.0, 1.0);
}
#else
uniform sampler2D subC, stencilC;          // the coarsest enabled level C: it covers every pixel
uniform sampler2D sub0, sub1, sub2;        // c_ℓ of the finer levels (those in FINE_LEVELS)
uniform sampler2D stencil0, stencil1, stencil2;
uniform sampler2D alpha0, alpha1, alpha2;
// COARSEST_LEVEL: C; COARSEST_SCALE: s_C (defined by the host, gpu/blend.cpp)
uniform float weights[3];   // w_ℓ of the finer levels
layout(location = 0) out vec4 finalOut;
layout(location = 1) out vec4 levelMap;  // the finest level with α > 0 (ℓ/255)

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  // α_ℓ and ĉ_ℓ fine to coarse, up to the first α = 1: below an opaque level nothing shows
  // (blendStep(1, f, c) = f), so the coarser levels are not read at all (as cpu_ref's base).
  float a0 = 0.0, a1 = 0.0, a2 = 0.0;
  vec3 c0 = vec3(0.0), c1 = vec3(0.0), c2 = vec3(0.0);
  bool opaque = false;
#if (FINE_LEVELS & 1) != 0
  a0 = levelZeroSample(sub0, stencil0, alpha0, weights[0], p, c0);
  opaque = a0 == 1.0;
#endif
#if (FINE_LEVELS & 2) != 0
  if (!opaque) {
    a1 = levelSample(sub1, stencil1, alpha1, 2, weights[1], p, c1);
    opaque = a1 == 1.0;
  }
#endif
#if (FINE_LEVELS & 4) != 0
  if (!opaque) {
    a2 = levelSample(sub2, stencil2, alpha2, 4, weights[2], p, c2);
    opaque = a2 == 1.0;
  }
#endif
  // 4. c' = ĉ_C (the coarsest covers every pixel), then coarse to fine each level with α > 0:
  // c' = α ĉ_ℓ + (1 − α) c' (blendStep(0, f, c) = c)
  vec3 result = opaque ? vec3(0.0) : coarsestSample(subC, stencilC, COARSEST_SCALE, p);
  int finest = COARSEST_LEVEL;
  if (a2 > 0.0) {
    result = a2 * c2 + (1.0 - a2) * result;
    finest = 2;
  }
  if (a1 > 0.0) {
    result = a1 * c1 + (1.0 - a1) * result;
    finest = 1;
  }
  if (a0 > 0.0) {
    result = a0 * c0 + (1.0 - a0) * result;
    finest = 0;
  }
  finalOut = vec4(result, 1.0);
  levelMap = vec4(float(finest) / 255.0, 0.0, 0.0, 1.0);
}
#endif
