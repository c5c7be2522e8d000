#version 330 core
// Example (docs/validate-your-own.md): SSAO with its own noise. The estimator is mrr's
// (the same kernel, occlusion test and range check: gpu/shaders/ssao.frag, SPEC §6), but each
// pixel's rotation comes from interleaved gradient noise (Jimenez 2014), as many real renderers
// do, not from mrr's PCG hash. Pixel for pixel it cannot match the oracle: `mrr compare
// --shaders examples/ssao-own-noise` FAILs at raw.L0. Judged as what it is, another draw of the
// same estimator, it passes: `mrr compare --shaders examples/ssao-own-noise --noise-aware`.
#include "common.glsl"
uniform sampler2D positionHit;  // level G-buffer: view position, hit
uniform sampler2D normalDepth;  // level G-buffer: view normal, depth
uniform sampler2D kernel;       // N×1 RGB32F: the host's hemisphere kernel (kernels.h)
uniform int samples;
uniform int level;
uniform float invScale;         // 1 / s_ℓ
uniform vec3 camera;            // (focal, cx, cy) of the full-res image
uniform float radius;
uniform float bias;
uniform bool tangentPlaneDepth;
layout(location = 0) out vec4 ao;

float smoothstep01(float x) {
  float t = clamp(x, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Range check: an occluder much farther from the receiver than R counts less.
float rangeCheck(float receiverDepth, float bufferDepth) {
  float distance = abs(receiverDepth - bufferDepth);
  if (distance <= radius) return 1.0;
  return smoothstep01(radius / distance);
}

// Occluder depth along the sample's view ray, from the texel's tangent plane (docs/spec.md §6.1).
float occluderDepth(vec3 s, vec3 texelNormal, vec3 texelPosition, float texelDepth) {
  if (!tangentPlaneDepth) return texelDepth;
  float along = dot(texelNormal, s);
  if (along * along <= kGrazingCosine2 * dot(s, s)) return texelDepth;  // common/shader_constants.h
  return -s.z * (dot(texelNormal, texelPosition) / along);
}

// Interleaved gradient noise (Jimenez, "Next generation post processing in Call of Duty: Advanced
// Warfare", 2014), offset per level so that the levels' patterns differ.
float interleavedGradientNoise(ivec2 pixel, int level) {
  vec2 q = vec2(pixel) + vec2(5.588238, 3.1115) * float(level);
  return fract(52.9829189 * fract(dot(q, vec2(0.06711056, 0.00583715))));
}

void ownSampleFrame(vec3 n, ivec2 pixel, int level, out vec3 t, out vec3 b) {
  float angle = 6.28318530717958647692 * interleavedGradientNoise(pixel, level);
  vec3 r = vec3(cos(angle), sin(angle), 0.0);
  vec3 tangent = r - n * dot(r, n);
  if (dot(tangent, tangent) < 1e-6) {  // r parallel to n: the perpendicular in-plane direction
    r = vec3(-sin(angle), cos(angle), 0.0);
    tangent = r - n * dot(r, n);
  }
  t = normalize(tangent);
  b = cross(n, t);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 ph = texelFetch(positionHit, pixel, 0);
  if (ph.w < 0.5) {
    ao = vec4(1.0);
    return;
  }
  vec3 p = ph.xyz;
  vec3 n = texelFetch(normalDepth, pixel, 0).xyz;
  // 1. per-pixel rotation about the normal from interleaved gradient noise (this renderer's own)
  vec3 t, b;
  ownSampleFrame(n, pixel, level, t, b);
  // 2. hemisphere samples: occluded when the occluder is in front by more than the bias
  vec2 size = vec2(textureSize(positionHit, 0));
  float receiverDepth = -p.z;
  float occlusion = 0.0;
  for (int i = 0; i < samples; ++i) {
    vec3 k = texelFetch(kernel, ivec2(i, 0), 0).xyz;
    vec3 s = p + radius * (t * k.x + b * k.y + n * k.z);
    float sampleDepth = -s.z;
    vec2 px = vec2(camera.y + camera.x * s.x / sampleDepth, camera.z - camera.x * s.y / sampleDepth) * invScale;
    if (!(sampleDepth > 0.0 && px.x >= 0.0 && px.y >= 0.0 && px.x < size.x && px.y < size.y)) continue;
    ivec2 texel = nearestLevelTexel(px, invScale);  // SPEC §0
    vec4 th = texelFetch(positionHit, texel, 0);
    if (th.w < 0.5) continue;  // background never occludes
    vec4 nd = texelFetch(normalDepth, texel, 0);
    float bufferDepth = occluderDepth(s, nd.xyz, th.xyz, nd.w);
    if (bufferDepth < sampleDepth - bias) occlusion += rangeCheck(receiverDepth, bufferDepth);
  }
  // 3. AO = 1 − occlusion / N
  ao = vec4(1.0 - occlusion / float(samples), 0.0, 0.0, 1.0);
}
