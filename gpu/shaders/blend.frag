#version 330 core
// Stage 6 — masked-bilinear upsampling and the blend (SPEC §5, the corrected Eq. 1), mirrors
// cpu_ref/blend.cpp. Two variants of one file:
//   (default)   one full-res pass per enabled level, coarse to fine; it writes ĉ_ℓ, α_ℓ,
//               c'_ℓ = α ĉ_ℓ + (1 − α) c'_coarser and the level map (--stages, probe, compare)
//   FINAL_ONLY  one full-res pass for every level at once: the final image and level map,
//               bit-identical to the per-level passes, as cpu_ref's blendFinalOnly: each pixel
//               visits the levels fine to coarse for their α first (stopping at α = 1, below
//               which nothing shows) and upsamples only the levels that change the result.

// 1. u = (p + ½)/s − ½ for full-res pixel p on a level of scale s: tap k's texel (clamped to
// the level grid) and bilinear weight b.
void bilinearTap(int k, ivec2 p, int scale, ivec2 last, out ivec2 q, out float b) {
  vec2 u = (vec2(p) + 0.5) / float(scale) - 0.5;
  vec2 f = floor(u);
  vec2 t = u - f;
  ivec2 o = ivec2(k & 1, k >> 1);
  q = clamp(ivec2(f) + o, ivec2(0), last);
  b = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
}

// 2. Over the four taps: â = Σ b a (all taps), the coverage Σ b over the rendered taps (S = 1)
// and, with `wantColor`, their colour Σ b c (masked bilinear: an unrendered tap is never read).
void upsample(sampler2D sub, sampler2D stencilMask, sampler2D alphaMask, int scale, ivec2 p, bool wantColor,
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
    alphaHat += b * texelFetch(alphaMask, q, 0).r;
    // masked bilinear: only rendered taps (S = 1) carry colour
    if (texelFetch(stencilMask, q, 0).r < 0.5) continue;
    coverage += b;
    if (wantColor) color += b * texelFetch(sub, q, 0).rgb;
  }
}

// 3. α = min(â·w, 1) where some tap is rendered, else 0.
float blendAlpha(float coverage, float alphaHat, float weight) {
  float alpha = 0.0;
  if (coverage > 0.0) alpha = min(alphaHat * weight, 1.0);
  return alpha;
}

#ifndef FINAL_ONLY
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
uniform sampler2D sub0, sub1, sub2, sub3;              // c_ℓ
uniform sampler2D stencil0, stencil1, stencil2, stencil3;  // S_ℓ
uniform sampler2D alpha0, alpha1, alpha2, alpha3;      // a_ℓ
uniform bool enabledLevel[4];
uniform float weights[4];  // w_ℓ
uniform int coarsestLevel;  // C, the coarsest enabled level: it covers every pixel
layout(location = 0) out vec4 finalOut;
layout(location = 1) out vec4 levelMap;  // the finest level with α > 0 (ℓ/255)

void levelTaps(int l, ivec2 p, bool wantColor, out vec3 color, out float coverage, out float alphaHat) {
  if (l == 0) upsample(sub0, stencil0, alpha0, 1, p, wantColor, color, coverage, alphaHat);
  else if (l == 1) upsample(sub1, stencil1, alpha1, 2, p, wantColor, color, coverage, alphaHat);
  else if (l == 2) upsample(sub2, stencil2, alpha2, 4, p, wantColor, color, coverage, alphaHat);
  else upsample(sub3, stencil3, alpha3, 8, p, wantColor, color, coverage, alphaHat);
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 color;
  float coverage, alphaHat;
  // α_ℓ fine to coarse; the finest level with α = 1 is the base: nothing coarser shows
  float alphas[4] = float[4](0.0, 0.0, 0.0, 0.0);
  int base = coarsestLevel;
  for (int l = 0; l < coarsestLevel; ++l) {
    if (!enabledLevel[l]) continue;
    levelTaps(l, p, false, color, coverage, alphaHat);
    alphas[l] = blendAlpha(coverage, alphaHat, weights[l]);
    if (alphas[l] == 1.0) {
      base = l;
      break;
    }
  }
  // c' = ĉ_base, then each finer level with α > 0 blended over it (blendStep(0, f, c) = c)
  levelTaps(base, p, true, color, coverage, alphaHat);
  vec3 result = coverage > 0.0 ? color / coverage : vec3(0.0);
  int finest = base;
  for (int l = base - 1; l >= 0; --l) {
    if (!enabledLevel[l] || alphas[l] == 0.0) continue;
    levelTaps(l, p, true, color, coverage, alphaHat);
    color /= coverage;  // > 0: α > 0
    result = alphas[l] * color + (1.0 - alphas[l]) * result;
    finest = l;
  }
  finalOut = vec4(result, 1.0);
  levelMap = vec4(float(finest) / 255.0, 0.0, 0.0, 1.0);
}
#endif
