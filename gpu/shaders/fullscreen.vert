#version 330 core
// The image-space passes' vertices: one triangle covering the viewport (GpuScene::drawFullscreen),
// or, with useRects, pixel rectangles given by their corners (GpuScene::drawRects): the passes
// that only have work near edges or inside S_ℓ draw those, and the rest of the target is never
// rasterised.
layout(location = 0) in vec2 corner;  // useRects: a rectangle corner, in pixels of the target
uniform bool useRects;
uniform vec2 targetSize;
void main() {
  if (useRects) {
    gl_Position = vec4(corner / targetSize * 2.0 - 1.0, 0.0, 1.0);
    return;
  }
  vec2 c = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(c * 2.0 - 1.0, 0.0, 1.0);
}
