#version 330 core
// Test pass: writes pixelHash(x, y, level) as two exact 16-bit halves, so a test can check the
// GLSL hash against common/hash.h bit for bit (SPEC §7).
#include "common.glsl"
uniform int level;
layout(location = 0) out vec4 halves;
void main() {
  uvec2 p = uvec2(gl_FragCoord.xy);
  uint h = pixelHash(p.x, p.y, uint(level));
  halves = vec4(float(h >> 16u), float(h & 65535u), hashToUnit(h), 1.0);
}
