#pragma once
// Numbers both paths must agree on, computed once on the host (SPEC §7).
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace mrr {

// Normalised samples of a Gaussian of variance sigma2 over [-r, r], r = ceil(3σ) (SPEC §3).
// sigma2 == 0 gives {1}: no blur.
std::vector<float> gaussianWeights(float sigma2);
int gaussianRadius(float sigma2);

// SSAO kernel (SPEC §6): n points in the +z hemisphere of the unit ball, denser near the
// centre (scale lerp(0.1, 1, (i/n)²)), from the PCG hash with a fixed seed: the same for
// every run, machine and thread count.
std::vector<glm::vec3> ssaoKernel(int n, uint32_t seed = 0x5eed5a0u);  // = kSsaoKernelSeed
// The kernels' seeds under sampling seed `seed` (--seed, SPEC §7): the base seed plus seed times
// the golden-ratio increment 0x9e3779b9, so seed 0 keeps the base (today's kernel) and other seeds
// start their counters far apart.
inline constexpr uint32_t kSsaoKernelSeed = 0x5eed5a0u;
inline constexpr uint32_t kSsgiKernelSeed = 0x51a61u;
constexpr uint32_t kernelSeed(uint32_t base, uint32_t seed) { return base + seed * 0x9e3779b9u; }

// Tap i of an n-tap regular grid over [−h, h] sits at gridTapFactor(i, n) · h (texel centres of
// the grid): SSM's blocker search and PCF. The GL port takes these factors from the host, so its
// taps land on the same bits.
inline float gridTapFactor(int i, int n) {
  return (static_cast<float>(i) + 0.5f) / static_cast<float>(n) * 2.0f - 1.0f;
}

}  // namespace mrr
