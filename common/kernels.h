#pragma once
// Numbers both paths must agree on, computed once on the host (SPEC §7, STYLE.md).
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
std::vector<glm::vec3> ssaoKernel(int n, uint32_t seed = 0x5eed5a0u);

// Tap i of an n-tap regular grid over [−h, h] sits at gridTapFactor(i, n) · h (texel centres of
// the grid): SSM's blocker search and PCF. The GL port takes these factors from the host, so its
// taps land on the same bits.
inline float gridTapFactor(int i, int n) {
  return (static_cast<float>(i) + 0.5f) / static_cast<float>(n) * 2.0f - 1.0f;
}

}  // namespace mrr
