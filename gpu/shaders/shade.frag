#version 330 core
// Stage 6 — the shaded image for viewing (SPEC §6), mirrors cpu_ref/shade.cpp: full-res albedo
// and N·L combined with the effect buffer. EFFECT is 0 (SSAO), 1 (SSM) or 2 (SSGI), set by
// the host (gpu/shade.cpp); the sky colour is a shared constant (common/shader_constants.h).
uniform sampler2D positionHit;  // G-buffer L0: view position, hit in w
uniform sampler2D normalDepth;  // G-buffer L0: view normal, depth
uniform sampler2D albedo;       // G-buffer L0: base colour
uniform sampler2D effect;       // the final effect buffer, W×H (AO, V, or indirect RGB)
uniform sampler2D shadowLit;    // SSGI: the one-tap shadow test (1 = lit)
uniform vec3 toLight;           // unit, view space: −normalize(the light's direction)
uniform vec3 lightColor;
layout(location = 0) out vec4 shaded;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  if (texelFetch(positionHit, p, 0).w < 0.5) {
    shaded = vec4(kSkyRed, kSkyGreen, kSkyBlue, 1.0);
    return;
  }
  // 1. direct: Lambert N·L
  float nl = max(dot(texelFetch(normalDepth, p, 0).xyz, toLight), 0.0);
  // 2. the effect's term
  vec3 e = texelFetch(effect, p, 0).rgb;
#if EFFECT == 1
  vec3 l = lightColor * (0.25 + 0.75 * nl * e.r);
#elif EFFECT == 2
  vec3 l = lightColor * (0.1 + 0.9 * nl * texelFetch(shadowLit, p, 0).r) + e;
#else
  vec3 l = lightColor * (0.45 * e.r + 0.55 * nl);
#endif
  shaded = vec4(texelFetch(albedo, p, 0).rgb * l, 1.0);
}
