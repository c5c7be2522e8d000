#version 330 core
// Pixel rectangles of the target (corners in pixels, two triangles each): the passes that
// only have work near edges draw these instead of the full-screen triangle (gpu/masks.cpp).
layout(location = 0) in vec2 corner;
uniform vec2 targetSize;
void main() { gl_Position = vec4(corner / targetSize * 2.0 - 1.0, 0.0, 1.0); }
