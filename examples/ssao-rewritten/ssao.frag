#version 330 core
// Example (docs/validate-your-own.md): SSAO rewritten with another structure that computes the
// same function as gpu/shaders/ssao.frag (SPEC §6): the sample frame as a matrix, the
// projection and the occlusion test each in a function, visibility summed instead of
// occlusion, the built-in smoothstep for the range check. `mrr compare --shaders
// examples/ssao-rewritten` passes: every value within ssao.same_input (common/tolerance.h).
#include "common.glsl"
uniform sampler2D positionHit;
uniform sampler2D normalDepth;
uniform sampler2D kernel;
uniform int samples;
uniform int level;
uniform float invScale;
uniform vec3 camera;
uniform float radius;
uniform float bias;
uniform bool tangentPlaneDepth;
layout(location = 0) out vec4 ao;

// A view-space point's texel on this level, or false when it falls outside or behind.
bool projectToTexel(vec3 s, out ivec2 texel) {
  float z = -s.z;
  vec2 px = vec2(camera.y + camera.x * s.x / z, camera.z - camera.x * s.y / z) * invScale;
  vec2 size = vec2(textureSize(positionHit, 0));
  texel = nearestLevelTexel(px, invScale);  // the texel whose sample is nearest (SPEC §0)
  return z > 0.0 && all(greaterThanEqual(px, vec2(0.0))) && all(lessThan(px, size));
}

// How much sample `s` is occluded, in [0, 1]: 0 when the buffer is not in front of it.
float occlusionAt(vec3 s, float receiverDepth) {
  ivec2 texel;
  if (!projectToTexel(s, texel)) return 0.0;
  vec4 th = texelFetch(positionHit, texel, 0);
  if (th.w < 0.5) return 0.0;  // the sky occludes nothing
  vec4 nd = texelFetch(normalDepth, texel, 0);
  float depth = nd.w;
  if (tangentPlaneDepth) {  // the occluder's depth along the sample's ray, on the texel's plane
    float along = dot(nd.xyz, s);
    if (along * along > kGrazingCosine2 * dot(s, s)) depth = -s.z * (dot(nd.xyz, th.xyz) / along);
  }
  if (!(depth < -s.z - bias)) return 0.0;
  float distance = abs(receiverDepth - depth);
  return distance <= radius ? 1.0 : smoothstep(0.0, 1.0, radius / distance);
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 ph = texelFetch(positionHit, pixel, 0);
  if (ph.w < 0.5) {
    ao = vec4(1.0);
    return;
  }
  vec3 n = texelFetch(normalDepth, pixel, 0).xyz;
  vec3 t, b;
  sampleFrame(n, pixel, level, t, b);
  mat3 frame = mat3(t, b, n);
  float visible = 0.0;
  for (int i = 0; i < samples; ++i) {
    vec3 s = ph.xyz + radius * (frame * texelFetch(kernel, ivec2(i, 0), 0).xyz);
    visible += 1.0 - occlusionAt(s, -ph.z);
  }
  ao = vec4(visible / float(samples), 0.0, 0.0, 1.0);
}
