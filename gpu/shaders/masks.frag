#version 330 core
// Stage 3 — mask pyramid, blur and stencils (SPEC §3), mirrors cpu_ref/masks.cpp. One file,
// one pass per step, at the output level's size. The host compiles a variant per pass shape
// (gpu/masks.cpp): STEP, and the step's FACTOR, RADIUS, DIRECTION, SOURCE_CHANNEL and
// WITH_STENCIL are constants, so loops unroll and the channel is a fixed swizzle. (As
// uniforms, with a loop bound and a vector index known only at run time, the passes took
// twice as long on llvmpipe: docs/port.md.)
//   STEP 1 max-pool: M_ℓ = max over the FACTOR×FACTOR block of `source` (E or M_{ℓ−1}); M_0
//     is E itself, read in place (channel SOURCE_CHANNEL of the edge target)
//   STEP 2 blur: one separable Gaussian pass along DIRECTION, clamp-to-edge (a_ℓ = G ∗ M_ℓ);
//     3. with WITH_STENCIL (the vertical pass) it also writes the stencil S_ℓ = [a_ℓ > 0]
//   STEP 4 closure: S_next ∨= max-pool(S_ℓ) over the FACTOR×FACTOR block
//   STEP 5 the level limit (SPEC §13 step 6, with --gaze or --prev-frame): M'_ℓ = M_ℓ where
//     LEVEL ≥ ℓ_min at the full-res pixel the level pixel holds (p·FACTOR + FACTOR/2, FACTOR = s_ℓ),
//     else 0; the blur then reads M'_ℓ (the pyramid above stays E's own)
// Level 0's passes are drawn only over the blocks near an edge, a coarser level's whole
// (gpu/masks.cpp); where a pass is not drawn, a_ℓ and S_ℓ keep their cleared 0, which is what the
// blur gives there.
uniform sampler2D source;    // the pass's input (channel SOURCE_CHANNEL)
uniform sampler2D previous;  // step 4: the coarser level's own stencil
#if STEP == 5
uniform sampler2D limit;     // limit.frag's output: ℓ_min in .a, padded full-res
#endif
#if STEP == 2
uniform float weights[2 * RADIUS + 1];  // the host's normalised Gaussian weights (kernels.h)
#endif
layout(location = 0) out vec4 result;
#if WITH_STENCIL
layout(location = 1) out vec4 stencil;  // 3. S_ℓ
#endif

float valueAt(ivec2 q) { return texelFetch(source, q, 0)[SOURCE_CHANNEL]; }

#if STEP != 2 && STEP != 5
float blockMax(ivec2 p) {
  float m = 0.0;
  for (int j = 0; j < FACTOR; ++j)
    for (int i = 0; i < FACTOR; ++i) m = max(m, valueAt(p * FACTOR + ivec2(i, j)));
  return m;
}
#endif

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float value = 0.0;
#if STEP == 1
  value = blockMax(p);
#elif STEP == 2
  ivec2 last = textureSize(source, 0) - 1;
  for (int i = -RADIUS; i <= RADIUS; ++i) value += weights[i + RADIUS] * valueAt(clamp(p + DIRECTION * i, ivec2(0), last));
#if WITH_STENCIL
  // 3. S_ℓ = [a_ℓ > 0]
  stencil = vec4(value > 0.0 ? 1.0 : 0.0, 0.0, 0.0, 1.0);
#endif
#elif STEP == 5
  int lmin = int(texelFetch(limit, p * FACTOR + FACTOR / 2, 0).a);
  value = LEVEL >= lmin ? valueAt(p) : 0.0;
#else
  value = max(texelFetch(previous, p, 0).r, blockMax(p));
#endif
  result = vec4(value, 0.0, 0.0, 1.0);
}
