#version 330 core
// Stage 4 for indirect light — SSGI after Ritschel et al. 2009 (SPEC §6, docs/spec.md §6.3),
// mirrors cpu_ref/ssgi.cpp. Two variants of this file:
//  - DIRECT_LIGHT: directLight, the light every pixel of a level sends: albedo × max(N·L, 0)
//    × one-tap shadow × light colour (background 0). Drawn at every pixel: any may be a sender.
//  - default: renderSsgi (ssgiAt), drawn with the stencil test, so it runs only where S_ℓ = 1:
//    N hemisphere samples, each projected pixel a sender patch of area πR²/N.
uniform sampler2D positionHit;  // level G-buffer: view position, hit
uniform sampler2D normalDepth;  // level G-buffer: view normal, depth
#ifdef DIRECT_LIGHT
#include "shadowmap.glsl"
uniform sampler2D albedo;       // level G-buffer: albedo
uniform vec3 toLight;           // view space, unit: −normalize(light direction), from the host
uniform vec3 lightColor;
layout(location = 0) out vec4 direct;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 ph = texelFetch(positionHit, pixel, 0);
  direct = vec4(0.0, 0.0, 0.0, 1.0);
  if (ph.w < 0.5) return;
  vec3 n = texelFetch(normalDepth, pixel, 0).xyz;
  float nl = max(dot(n, toLight), 0.0);
  if (nl == 0.0) return;
  Receiver r = receiverAt(viewToWorld(ph.xyz), viewDirectionToWorld(n));
  float lit = shadowTest(r);
  direct = vec4(texelFetch(albedo, pixel, 0).rgb * nl * lit * lightColor, 1.0);
}
#else
#include "common.glsl"
uniform sampler2D direct;       // the level's direct light (the DIRECT_LIGHT variant), RGB
uniform sampler2D kernel;       // N×1 RGB32F: the host's hemisphere kernel (kernels.h)
uniform int samples;
uniform int level;
uniform uint seed;              // the sampling seed (--seed; 0 = mrr's own)
uniform float invScale;         // 1 / s_ℓ
uniform vec3 camera;            // (focal, cx, cy) of the full-res image
uniform float radius;           // R
uniform float patchArea;        // A = πR²/N
uniform float minDistance2;     // (R/4)²: the sender distance is clamped to it
layout(location = 0) out vec4 indirect;

const float kPi = 3.14159265358979323846;  // as cpu_ref/ssgi.cpp's: π itself, not a choice
// kGrazingCosine (senders this close to either tangent plane are coplanar): common/shader_constants.h

// Ritschel et al. 2009, Eq. 2: the form factor of a sender patch of area A at distance d,
// A cos θ_s cos θ_r / (π d²), with d clamped to R/4 (docs/spec.md §6.3).
float patchFormFactor(float area, float cosSender, float cosReceiver, float distance2) {
  return area * cosSender * cosReceiver / (kPi * max(distance2, minDistance2));
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 ph = texelFetch(positionHit, pixel, 0);
  if (ph.w < 0.5) {
    indirect = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  vec3 p = ph.xyz;
  vec3 n = texelFetch(normalDepth, pixel, 0).xyz;
  // 1. the hemisphere frame, rotated per pixel (shared with SSAO)
  vec3 t, b;
  sampleFrame(n, pixel, level, seed, t, b);
  vec2 size = vec2(textureSize(positionHit, 0));
  vec3 sum = vec3(0.0);
  for (int i = 0; i < samples; ++i) {
    vec3 k = texelFetch(kernel, ivec2(i, 0), 0).xyz;
    // 2. the sample's projected pixel is the sender
    vec3 s = p + radius * (t * k.x + b * k.y + n * k.z);
    float sampleDepth = -s.z;
    vec2 px = vec2(camera.y + camera.x * s.x / sampleDepth, camera.z - camera.x * s.y / sampleDepth) * invScale;
    if (!(sampleDepth > 0.0 && px.x >= 0.0 && px.y >= 0.0 && px.x < size.x && px.y < size.y)) continue;
    ivec2 texel = nearestLevelTexel(px, invScale);  // SPEC §0
    vec4 sender = texelFetch(positionHit, texel, 0);
    if (sender.w < 0.5) continue;  // background sends nothing
    // 3. its direct light through the patch form factor
    vec3 toSender = sender.xyz - p;
    float distance2 = dot(toSender, toSender);
    if (distance2 == 0.0) continue;
    float inv = 1.0 / sqrt(distance2);
    float cosReceiver = dot(n, toSender) * inv;
    float cosSender = -dot(texelFetch(normalDepth, texel, 0).xyz, toSender) * inv;
    if (cosReceiver <= kGrazingCosine || cosSender <= kGrazingCosine) continue;
    float f = patchFormFactor(patchArea, cosSender, cosReceiver, distance2);
    sum += f * texelFetch(direct, texel, 0).rgb;
  }
  indirect = vec4(sum, 1.0);
}
#endif
