#version 330 core
// Stage 1 — G-buffer (SPEC §1), mirrors cpu_ref/gbuffer.cpp.
in vec3 viewPosition;
in vec3 viewNormal;
in vec2 surfaceTexcoord;
#include "cutout.glsl"
uniform vec3 albedo;
layout(location = 0) out vec4 outPositionHit;  // view-space position, hit = 1
layout(location = 1) out vec4 outNormalDepth;  // view-space normal, linear depth z = −p.z
layout(location = 2) out vec4 outAlbedo;
void main() {
  // 0. alpha cutout (docs/spec.md §1.1): a transparent texel is no surface, the ray goes on
  if (transparentAt(surfaceTexcoord)) discard;
  // 1. shading normal: interpolated, normalised, flipped to face the camera
  float len = length(viewNormal);
  vec3 n = len > 0.0 ? viewNormal / len : -normalize(viewPosition);
  if (dot(n, viewPosition) > 0.0) n = -n;
  outPositionHit = vec4(viewPosition, 1.0);
  outNormalDepth = vec4(n, -viewPosition.z);
  outAlbedo = vec4(albedo, 1.0);
}
