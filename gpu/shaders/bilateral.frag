#version 330 core
// Stage 4 (SSAO) — mask-aware bilateral blur of a sub-image (SPEC §4), mirrors cpu_ref/bilateral.cpp:
// taps weighted by a spatial Gaussian × depth similarity × normal similarity × S(q),
// normalised over valid taps. Drawn with the stencil test (S = 1 only).
uniform sampler2D image;        // the raw sub-image (channel r)
uniform sampler2D stencilMask;  // S_ℓ
uniform sampler2D positionHit;  // level G-buffer
uniform sampler2D normalDepth;
uniform int radius;
uniform float spatial[289];     // (2r+1)² host weights, row-major (Constants::Bilateral)
uniform float sigmaDepth;
uniform float normalPower;
layout(location = 0) out vec4 result;

#include "bilateral.glsl"

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(image, 0);
  float centre = texelFetch(image, p, 0).r;
  if (texelFetch(positionHit, p, 0).w < 0.5) {
    result = vec4(centre, 0.0, 0.0, 1.0);
    return;
  }
  float zp = texelFetch(normalDepth, p, 0).w;
  vec3 np = texelFetch(normalDepth, p, 0).xyz;
  float weightSum = 0.0, sum = 0.0;
  int side = 2 * radius + 1;
  for (int j = -radius; j <= radius; ++j)
    for (int i = -radius; i <= radius; ++i) {
      ivec2 q = p + ivec2(i, j);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      if (texelFetch(stencilMask, q, 0).r < 0.5 || texelFetch(positionHit, q, 0).w < 0.5) continue;
      vec4 nq = texelFetch(normalDepth, q, 0);
      // 1. depth similarity, relative to the centre's depth
      float dz = (nq.w - zp) / (sigmaDepth * zp);
      float depthWeight = exp(-dz * dz);
      // 2. normal similarity
      float normalWeight = normalSimilarity(max(dot(np, nq.xyz), 0.0), normalPower);
      // 3. spatial Gaussian × depth × normal
      float w = spatial[(j + radius) * side + i + radius] * depthWeight * normalWeight;
      if (w == 0.0) continue;
      weightSum += w;
      sum += w * texelFetch(image, q, 0).r;
    }
  // 4. normalise over the valid taps
  result = vec4(sum / weightSum, 0.0, 0.0, 1.0);
}
