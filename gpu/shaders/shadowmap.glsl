// Shared by the shaders that read the light's shadow map (pasted where a shader says
// #include "shadowmap.glsl"): shadowmap.vert, shadowmap.frag's one-tap test, ssm.frag and
// ssgi.frag's direct light. Mirrors cpu_ref/shadowmap.h: ShadowMap::lightCoordinates,
// ShadowMap::depthAt, receiverAt, shadowTest (SPEC §6 SSM, docs/spec.md §6.4). The uniforms
// are set by gpu/shadowmap.cpp: bindShadowMap, from the oracle's own frame (shadowMapFrame).
uniform sampler2D shadowMap;  // size² R32F: distance from the light plane; kNoBlocker on a miss
uniform int mapSize;
uniform float mapTexel;       // world units per texel
uniform vec3 mapOrigin;       // corner of texel (0, 0) on the light plane
uniform vec3 mapRight, mapUp, mapForward;
uniform float biasTexels;     // receiver offset and depth bias, in texels
uniform vec3 viewEye, viewRight, viewUp, viewForward;  // the camera's world-space basis (View)

// View::directionToWorld and View::toWorld.
vec3 viewDirectionToWorld(vec3 v) { return viewRight * v.x + viewUp * v.y - viewForward * v.z; }
vec3 viewToWorld(vec3 v) { return viewEye + viewDirectionToWorld(v); }

// Continuous texel coordinates (u, v) and the distance from the light plane, of a world point.
vec3 lightCoordinates(vec3 world) {
  vec3 d = world - mapOrigin;
  return vec3(dot(d, mapRight) / mapTexel, dot(d, mapUp) / mapTexel, dot(d, mapForward));
}

// The stored depth at the texel holding (u, v); outside the map nothing blocks.
float depthAt(float u, float v) {
  float size = float(mapSize);
  if (!(u >= 0.0 && v >= 0.0 && u < size && v < size)) return kNoBlocker;  // common/shader_constants.h
  return texelFetch(shadowMap, ivec2(int(u), int(v)), 0).r;
}

// A receiver in light space: its world position pushed along its normal by the bias, and its
// biased depth (docs/spec.md §6.4). Shared by the one-tap test and PCSS so both agree.
struct Receiver {
  float u, v;   // texel coordinates
  float depth;  // distance from the light plane, minus the depth bias
};
Receiver receiverAt(vec3 worldPosition, vec3 worldNormal) {
  float bias = biasTexels * mapTexel;
  vec3 l = lightCoordinates(worldPosition + worldNormal * bias);
  return Receiver(l.x, l.y, l.z - bias);
}

// One shadow-map test: 1 = lit, 0 = in shadow.
float shadowTest(Receiver r) { return r.depth <= depthAt(r.u, r.v) ? 1.0 : 0.0; }
