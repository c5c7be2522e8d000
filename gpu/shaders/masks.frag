#version 330 core
// Stage 3 — mask pyramid, blur and stencils (SPEC §3), mirrors cpu_ref/masks.cpp. One
// program, four steps chosen by `step`, each a full-screen pass at the output level's size:
//   1 max-pool: M_ℓ = max over the factor×factor block of `source` (edges or M_{ℓ−1})
//   2 blur: one separable Gaussian pass along `direction`, clamp-to-edge (a_ℓ = G ∗ M_ℓ)
//   3 stencil: S_ℓ = [a_ℓ > 0]
//   4 closure: S_next ∨= max-pool(S_ℓ) over the factor×factor block
uniform int step;
uniform sampler2D source;    // the pass's input (channel r; step 1: channel sourceChannel)
uniform int sourceChannel;   // step 1: E's channel in the edge target (0 for M_{ℓ−1})
uniform sampler2D previous;  // step 4: the coarser level's own stencil
uniform int factor;          // steps 1 and 4
uniform ivec2 direction;     // step 2: (1, 0) or (0, 1)
uniform int radius;          // step 2: r_ℓ = ceil(3σ_ℓ)
uniform float weights[49];   // step 2: the host's normalised Gaussian weights (kernels.h)
layout(location = 0) out vec4 result;

float blockMax(ivec2 p) {
  float m = 0.0;
  for (int j = 0; j < factor; ++j)
    for (int i = 0; i < factor; ++i) m = max(m, texelFetch(source, p * factor + ivec2(i, j), 0)[sourceChannel]);
  return m;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float value = 0.0;
  if (step == 1) {
    value = blockMax(p);
  } else if (step == 2) {
    ivec2 last = textureSize(source, 0) - 1;
    for (int i = -radius; i <= radius; ++i)
      value += weights[i + radius] * texelFetch(source, clamp(p + direction * i, ivec2(0), last), 0).r;
  } else if (step == 3) {
    value = texelFetch(source, p, 0).r > 0.0 ? 1.0 : 0.0;
  } else {
    value = max(texelFetch(previous, p, 0).r, blockMax(p));
  }
  result = vec4(value, 0.0, 0.0, 1.0);
}
