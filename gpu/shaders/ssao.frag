#version 330 core
// Stage 4 — the SSAO sub-image (SPEC §4, §6), mirrors cpu_ref/ssao.cpp: drawn with the stencil
// test, so it runs only where S_ℓ = 1.
#include "common.glsl"
uniform sampler2D positionHit;  // level G-buffer: view position, hit
uniform sampler2D normalDepth;  // level G-buffer: view normal, depth
uniform sampler2D kernel;       // N×1 RGB32F: the host's hemisphere kernel (kernels.h)
uniform int samples;
uniform int level;
uniform uint seed;              // the sampling seed (--seed; 0 = mrr's own)
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

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 ph = texelFetch(positionHit, pixel, 0);
  if (ph.w < 0.5) {
    ao = vec4(1.0);
    return;
  }
  vec3 p = ph.xyz;
  vec3 n = texelFetch(normalDepth, pixel, 0).xyz;
  // 1. per-pixel rotation about the normal from the integer hash of (x, y, level)
  vec3 t, b;
  sampleFrame(n, pixel, level, seed, t, b);
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
