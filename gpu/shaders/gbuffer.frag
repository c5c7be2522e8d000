#version 330 core
// Stage 1 — G-buffer (SPEC §1), mirrors cpu_ref/gbuffer.cpp. Two variants of one file:
//   (default)  level 0 rasterised (gbuffer.vert): renderGBuffer
//   SUBSAMPLE  level ℓ ≥ 1, a copy of level 0 at the full-res pixels its pixels sample
//              (fullscreen.vert): subsampleGBuffer
layout(location = 0) out vec4 outPositionHit;  // view-space position, hit = 1
layout(location = 1) out vec4 outNormalDepth;  // view-space normal, linear depth z = −p.z
layout(location = 2) out vec4 outAlbedo;
#ifdef SUBSAMPLE
uniform sampler2D fullPositionHit;  // level 0's targets
uniform sampler2D fullNormalDepth;
uniform sampler2D fullAlbedo;
uniform int scale;  // s_ℓ = 2^ℓ
void main() {
  // 1. the full-res pixel this level pixel samples (SPEC §0: x·s + ⌊s/2⌋), clamped to the grid
  ivec2 p = min(ivec2(gl_FragCoord.xy) * scale + scale / 2, textureSize(fullPositionHit, 0) - 1);
  // 2. its every channel, copied
  outPositionHit = texelFetch(fullPositionHit, p, 0);
  outNormalDepth = texelFetch(fullNormalDepth, p, 0);
  outAlbedo = texelFetch(fullAlbedo, p, 0);
}
#else
in vec3 viewPosition;
in vec3 viewNormal;
in vec2 surfaceTexcoord;
#include "cutout.glsl"
#include "albedo.glsl"
uniform vec3 albedo;  // the factor
uniform float farDepth;  // the linear depth that maps to 1 in the depth buffer
void main() {
  // 0. alpha cutout (docs/spec.md §1.1): a transparent texel is no surface, the ray goes on
  if (transparentAt(surfaceTexcoord)) discard;
  // 1. shading normal: interpolated, normalised, flipped to face the camera
  float len = length(viewNormal);
  vec3 n = len > 0.0 ? viewNormal / len : -normalize(viewPosition);
  if (dot(n, viewPosition) > 0.0) n = -n;
  outPositionHit = vec4(viewPosition, 1.0);
  outNormalDepth = vec4(n, -viewPosition.z);
  outAlbedo = vec4(albedoAt(albedo, surfaceTexcoord), 1.0);  // §1.2: factor × texel
  // 2. the depth test orders surfaces by linear depth (uniform precision from the eye out), not
  // by the projection's 1/z, whose precision near a close near plane (a camera inside a room)
  // is too coarse to order a picture and the wall behind it
  gl_FragDepth = -viewPosition.z / farDepth;
}
#endif
