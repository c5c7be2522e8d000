#include "common/kernels.h"

#include <cmath>

#include "common/hash.h"

namespace mrr {

int gaussianRadius(float sigma2) {
  if (sigma2 <= 0.0f) return 0;
  return static_cast<int>(std::ceil(3.0f * std::sqrt(sigma2)));
}

// SPEC §3: separable Gaussian of variance σ², radius ceil(3σ), normalised over the kernel.
std::vector<float> gaussianWeights(float sigma2) {
  const int r = gaussianRadius(sigma2);
  if (r == 0) return {1.0f};
  std::vector<float> w(static_cast<size_t>(2 * r + 1));
  double sum = 0.0;
  for (int i = -r; i <= r; ++i) {
    const double v = std::exp(-static_cast<double>(i * i) / (2.0 * sigma2));
    w[static_cast<size_t>(i + r)] = static_cast<float>(v);
    sum += v;
  }
  for (float& v : w) v = static_cast<float>(v / sum);
  return w;
}

// SPEC §6: hemisphere kernel, a sequence of PCG hashes of (seed + counter).
std::vector<glm::vec3> ssaoKernel(int n, uint32_t seed) {
  std::vector<glm::vec3> kernel;
  kernel.reserve(static_cast<size_t>(n));
  uint32_t counter = 0;
  auto next = [&]() { return hashToUnit(pcgHash(seed + counter++)); };
  for (int i = 0; i < n; ++i) {
    glm::vec3 v;
    float len2 = 0.0f;
    do {  // rejection-sample the unit half-ball, so directions are uniform
      // Drawn z, then y, then x, in statements: the vector was once built from three calls in
      // one expression, whose order C++ leaves unspecified (GCC went right to left); this keeps
      // those bits and makes them the same under any compiler (docs/spec.md §7.1).
      const float z = next();
      const float y = next() * 2.0f - 1.0f;
      const float x = next() * 2.0f - 1.0f;
      v = glm::vec3(x, y, z);
      len2 = glm::dot(v, v);
    } while (len2 > 1.0f || len2 < 1e-4f);
    v /= std::sqrt(len2);
    const float t = static_cast<float>(i) / static_cast<float>(n);
    const float scale = 0.1f + 0.9f * t * t;  // denser near the centre
    kernel.push_back(v * (scale * (0.2f + 0.8f * next())));
  }
  return kernel;
}

}  // namespace mrr
