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

// A receiver in light space (docs/spec.md §6.4): its world position pushed along its normal by
// the bias, its biased depth, and the depth slope of its tangent plane, so that a tap at another
// texel is compared with the plane's depth there. Shared by the one-tap test and PCSS.
struct Receiver {
  float u, v;            // texel coordinates
  float depth;           // distance from the light plane, minus the depth bias
  float slopeU, slopeV;  // the tangent plane's depth change per texel in u and v
  bool facesLight;       // n·l > 0: the visible side faces the light
};
Receiver receiverAt(vec3 worldPosition, vec3 worldNormal) {
  // 1. normal offset and a constant depth bias, both in texels
  float bias = biasTexels * mapTexel;
  vec3 l = lightCoordinates(worldPosition + worldNormal * bias);
  // 2. which side of the surface the light is on (mapForward: the way the light travels)
  float nForward = dot(worldNormal, mapForward);
  // 3. the tangent plane's depth slope per texel, |n·forward| capped near grazing
  float cosine = min(nForward, -kReceiverMinCosine);  // common/shader_constants.h
  return Receiver(l.x, l.y, l.z - bias, -dot(worldNormal, mapRight) / cosine * mapTexel,
                  -dot(worldNormal, mapUp) / cosine * mapTexel, nForward < 0.0);
}

// The receiver's depth at a tap (du, dv) texels away, on its tangent plane.
float receiverDepthAt(Receiver r, float du, float dv) { return r.depth + du * r.slopeU + dv * r.slopeV; }

// One shadow-map test: 1 = lit, 0 = in shadow. A surface whose visible side faces away from the
// light is in its own shadow, whatever the map holds.
float shadowTest(Receiver r) { return r.facesLight && r.depth <= depthAt(r.u, r.v) ? 1.0 : 0.0; }
