#pragma once
// The integer hash both paths use for per-pixel sample rotations (SPEC §7). It is the PCG
// hash of Jarzynski & Olano (JCGT 2020), written only with 32-bit unsigned wrap-around
// arithmetic so that GLSL 3.30 `uint` computes the same bits (gpu/shaders/common.glsl).
#include <cstdint>

namespace mrr {

constexpr uint32_t pcgHash(uint32_t v) {
  uint32_t state = v * 747796405u + 2891336453u;
  uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Hash of a level pixel: (x, y, level) -> 32 bits.
constexpr uint32_t pixelHash(uint32_t x, uint32_t y, uint32_t level) {
  return pcgHash(x + pcgHash(y + pcgHash(level)));
}

// The hash of a level pixel's sample rotation under sampling seed `seed` (--seed, SPEC §7):
// the pixel hash of (x, y, level + 4 seed). Seed 0 is pixelHash itself (today's bits); each
// other seed moves the level argument past the four levels, so its rotations are those of
// another, independent hash input.
constexpr uint32_t rotationHash(uint32_t x, uint32_t y, uint32_t level, uint32_t seed) {
  return pixelHash(x, y, level + 4u * seed);
}

// The top 24 bits as a float in [0, 1): exact in float32 on both paths.
constexpr float hashToUnit(uint32_t h) {
  return static_cast<float>(h >> 8u) * (1.0f / 16777216.0f);
}

}  // namespace mrr
