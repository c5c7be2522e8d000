#version 330 core
// Stage 6 — masked-bilinear upsampling and one blend step (SPEC §5, the corrected Eq. 1),
// mirrors cpu_ref/blend.cpp. One full-res pass per enabled level, coarse to fine; it writes
// ĉ_ℓ, α_ℓ and c'_ℓ = α ĉ_ℓ + (1 − α) c'_coarser.
uniform sampler2D sub;          // c_ℓ at level resolution (rgb)
uniform sampler2D stencilMask;  // S_ℓ
uniform sampler2D alphaMask;    // a_ℓ
uniform sampler2D coarser;      // c'_{next coarser enabled} at full res (unused at the coarsest)
uniform bool coarsest;
uniform int scale;              // s_ℓ
uniform float weight;           // w_ℓ
layout(location = 0) out vec4 cHat;
layout(location = 1) out vec4 alphaOut;
layout(location = 2) out vec4 composite;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(sub, 0) - 1;
  // 1. u = (p + ½)/s − ½, the four taps clamped to the level grid
  vec2 u = (vec2(p) + 0.5) / float(scale) - 0.5;
  vec2 f = floor(u);
  vec2 t = u - f;
  ivec2 base = ivec2(f);
  vec3 color = vec3(0.0);
  float coverage = 0.0, alphaHat = 0.0;
  for (int k = 0; k < 4; ++k) {
    ivec2 o = ivec2(k & 1, k >> 1);
    ivec2 q = clamp(base + o, ivec2(0), last);
    float b = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
    // 2. â = Σ b_q a(q), over all taps
    alphaHat += b * texelFetch(alphaMask, q, 0).r;
    // masked bilinear: only rendered taps (S = 1) carry colour
    if (texelFetch(stencilMask, q, 0).r < 0.5) continue;
    coverage += b;
    color += b * texelFetch(sub, q, 0).rgb;
  }
  float alpha = 0.0;
  if (coverage > 0.0) {
    color /= coverage;
    alpha = min(alphaHat * weight, 1.0);  // 3. α = min(â·w, 1)
  }
  if (coarsest) alpha = coverage > 0.0 ? 1.0 : 0.0;
  vec3 below = coarsest ? vec3(0.0) : texelFetch(coarser, p, 0).rgb;
  // 4. c'_ℓ = α ĉ_ℓ + (1 − α) c'_coarser (written out, not mix(), to keep the host's order)
  vec3 result = coarsest ? color : alpha * color + (1.0 - alpha) * below;
  cHat = vec4(color, 1.0);
  alphaOut = vec4(alpha, 0.0, 0.0, 1.0);
  composite = vec4(result, 1.0);
}
