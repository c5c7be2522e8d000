#version 330 core
// Stage 1 — G-buffer (SPEC §1), mirrors cpu_ref/gbuffer.cpp: the full-res level is rasterised,
// sampling the pixel centres (x+½, y+½) of the padded grid (gbuffer.frag's SUBSAMPLE variant
// makes the coarser levels from it).
layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec3 worldNormal;
layout(location = 2) in vec2 texcoord;  // meshes with an alpha cutout or a texture only (else (0, 0))
uniform mat4 worldToView;
// Full-res pixel of a view point: px = cx + f x/(−z), py = cy − f y/(−z), mapped so that GL's
// row 0 is image row 0 (readback needs no flip): (2f/Wp, 2cx/Wp − 1, −2f/Hp, 2cy/Hp − 1).
uniform vec4 projection;
uniform vec2 depthMapping;  // z_clip = A z + B (standard perspective depth for near/far)
out vec3 viewPosition;
out vec3 viewNormal;
out vec2 surfaceTexcoord;
void main() {
  vec4 p = worldToView * vec4(worldPosition, 1.0);
  viewPosition = p.xyz;
  viewNormal = mat3(worldToView) * worldNormal;
  surfaceTexcoord = texcoord;
  float w = -p.z;
  gl_Position = vec4(projection.x * p.x + projection.y * w, projection.z * p.y + projection.w * w,
                     depthMapping.x * p.z + depthMapping.y, w);
}
