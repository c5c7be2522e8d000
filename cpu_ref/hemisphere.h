#pragma once
// The per-pixel sample frame shared by SSAO and SSGI (SPEC §6, §7): the host kernel lives in
// a tangent frame around the normal, rotated by an angle from the hash of (x, y, level).
#include <glm/glm.hpp>

#include <cmath>
#include <cstdint>

#include "common/hash.h"

namespace mrr {

struct SampleFrame {
  glm::vec3 t, b, n;  // tangent, bitangent, normal (view space)
  float angle = 0.0f; // the rotation, radians
  glm::vec3 apply(const glm::vec3& k) const { return t * k.x + b * k.y + n * k.z; }
};

// `seed`: the sampling seed (--seed; 0 = mrr's own rotations), common/hash.h rotationHash.
inline SampleFrame sampleFrame(const glm::vec3& n, int x, int y, int level, uint32_t seed = 0) {
  constexpr float kTwoPi = 6.28318530717958647692f;
  SampleFrame f;
  f.n = n;
  // 1. per-pixel rotation about the normal from the integer hash of (x, y, level, seed)
  f.angle = kTwoPi * hashToUnit(rotationHash(static_cast<uint32_t>(x), static_cast<uint32_t>(y),
                                             static_cast<uint32_t>(level), seed));
  glm::vec3 r(std::cos(f.angle), std::sin(f.angle), 0.0f);
  glm::vec3 t = r - n * glm::dot(r, n);
  if (glm::dot(t, t) < 1e-6f) {  // r ∥ n: take the perpendicular in-plane direction
    r = glm::vec3(-std::sin(f.angle), std::cos(f.angle), 0.0f);
    t = r - n * glm::dot(r, n);
  }
  f.t = glm::normalize(t);
  f.b = glm::cross(n, f.t);
  return f;
}

}  // namespace mrr
