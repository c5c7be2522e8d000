#version 330 core
// Stage 3 — mask pyramid, blur and stencils (SPEC §3), mirrors cpu_ref/masks.cpp. One
// program, steps chosen by `step`, each a pass at the output level's size:
//   1 max-pool: M_ℓ = max over the factor×factor block of `source` (E or M_{ℓ−1}); M_0 is E
//     itself, read in place (channel sourceChannel of the edge target)
//   2 blur: one separable Gaussian pass along `direction`, clamp-to-edge (a_ℓ = G ∗ M_ℓ);
//   3 the vertical pass also writes the stencil S_ℓ = [a_ℓ > 0] (withStencil)
//   4 closure: S_next ∨= max-pool(S_ℓ) over the factor×factor block
// The blur passes are drawn only over the blocks near an edge (gpu/masks.cpp: blurRects);
// elsewhere a_ℓ and S_ℓ keep their cleared 0, which is what the blur gives there.
uniform int step;
uniform sampler2D source;    // the pass's input (channel sourceChannel)
uniform sampler2D previous;  // step 4: the coarser level's own stencil
uniform int sourceChannel;   // E's channel in the edge target; 0 for every other input
uniform int factor;          // steps 1 and 4
uniform ivec2 direction;     // step 2: (1, 0) or (0, 1)
uniform int radius;          // step 2: r_ℓ = ceil(3σ_ℓ)
uniform float weights[49];   // step 2: the host's normalised Gaussian weights (kernels.h)
uniform bool withStencil;    // step 2, vertical: step 3 too
layout(location = 0) out vec4 result;
layout(location = 1) out vec4 stencil;  // step 3: S_ℓ

float valueAt(ivec2 q) { return texelFetch(source, q, 0)[sourceChannel]; }

float blockMax(ivec2 p) {
  float m = 0.0;
  for (int j = 0; j < factor; ++j)
    for (int i = 0; i < factor; ++i) m = max(m, valueAt(p * factor + ivec2(i, j)));
  return m;
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float value = 0.0;
  if (step == 1) {
    value = blockMax(p);
  } else if (step == 2) {
    ivec2 last = textureSize(source, 0) - 1;
    for (int i = -radius; i <= radius; ++i) value += weights[i + radius] * valueAt(clamp(p + direction * i, ivec2(0), last));
    // 3. S_ℓ = [a_ℓ > 0]
    stencil = vec4(withStencil && value > 0.0 ? 1.0 : 0.0, 0.0, 0.0, 1.0);
  } else {
    value = max(texelFetch(previous, p, 0).r, blockMax(p));
  }
  result = vec4(value, 0.0, 0.0, 1.0);
}
