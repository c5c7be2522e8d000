#version 330 core
// The light's shadow map (SPEC §6 SSM), mirrors cpu_ref/shadowmap.cpp: renderShadowMap. The
// oracle casts one ray per texel centre from the light plane; here the scene is rasterised
// orthographically onto the same texel grid (GL samples pixel centres), so the two differ only
// where a triangle edge passes through a texel centre.
#include "shadowmap.glsl"
layout(location = 0) in vec3 worldPosition;
layout(location = 2) in vec2 texcoord;  // meshes with an alpha cutout only (else (0, 0))
uniform float farDepth;  // ShadowMap::farDepth: orders surfaces only, the stored depth is lightDepth
out float lightDepth;
out vec2 surfaceTexcoord;
// (Steps 1–2, the light's basis and the square fitted to the bounds, are the host's
// shadowMapFrame, shared with the oracle.)
void main() {
  // 3. each surface onto the texel grid; the depth test keeps the nearest at each texel centre,
  // as the oracle's ray per texel centre finds it
  vec3 l = lightCoordinates(worldPosition);  // texel coordinates (u, v), distance from the plane
  lightDepth = l.z;
  surfaceTexcoord = texcoord;
  // texel (x, y) is GL pixel (x, y): row 0 of the map is row 0 of the target (no flip)
  gl_Position = vec4(l.xy * (2.0 / float(mapSize)) - 1.0, 2.0 * l.z / farDepth - 1.0, 1.0);
}
