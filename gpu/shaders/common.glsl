// Shared by the port's shaders (pasted where a shader says #include "common.glsl"): the PCG
// hash of common/hash.h, in GLSL 3.30 uint arithmetic (32-bit wrap-around, as in C++).
uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
uint pixelHash(uint x, uint y, uint level) { return pcgHash(x + pcgHash(y + pcgHash(level))); }
float hashToUnit(uint h) { return float(h >> 8u) * (1.0 / 16777216.0); }
