// Shared by the port's shaders (pasted where a shader says #include "common.glsl"): the PCG
// hash of common/hash.h, in GLSL 3.30 uint arithmetic (32-bit wrap-around, as in C++).
uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
uint pixelHash(uint x, uint y, uint level) { return pcgHash(x + pcgHash(y + pcgHash(level))); }
uint rotationHash(uint x, uint y, uint level, uint seed) { return pixelHash(x, y, level + 4u * seed); }
float hashToUnit(uint h) { return float(h >> 8u) * (1.0 / 16777216.0); }

// The per-pixel sample frame shared by SSAO and SSGI (SPEC §6, §7), mirrors
// cpu_ref/hemisphere.h: sampleFrame. The host kernel lives in a tangent frame (t, b, n),
// rotated about the normal by an angle from the hash of (x, y, level).
void sampleFrame(vec3 n, ivec2 pixel, int level, uint seed, out vec3 t, out vec3 b) {
  // 1. per-pixel rotation about the normal from the integer hash of (x, y, level, seed)
  float angle = 6.28318530717958647692 * hashToUnit(rotationHash(uint(pixel.x), uint(pixel.y), uint(level), seed));
  vec3 r = vec3(cos(angle), sin(angle), 0.0);
  vec3 tangent = r - n * dot(r, n);
  if (dot(tangent, tangent) < 1e-6) {  // r ∥ n: take the perpendicular in-plane direction
    r = vec3(-sin(angle), cos(angle), 0.0);
    tangent = r - n * dot(r, n);
  }
  t = normalize(tangent);
  b = cross(n, t);
}
// mrr's own sampling (seed 0): for shaders written before --seed.
void sampleFrame(vec3 n, ivec2 pixel, int level, out vec3 t, out vec3 b) { sampleFrame(n, pixel, level, 0u, t, b); }

// SPEC §0, mirrors common/frame.h: nearestLevelTexel. The level texel whose sample is nearest an
// on-screen point at level coordinates u = q/s: the samples sit at x·s + ⌊s/2⌋ + ½, half a
// full-res pixel past their blocks' centres above level 0, so floor(u − ½/s) there (clamped at 0).
ivec2 nearestLevelTexel(vec2 u, float invScale) {
  vec2 shifted = invScale < 1.0 ? u - 0.5 * invScale : u;
  return max(ivec2(floor(shifted)), ivec2(0));
}
