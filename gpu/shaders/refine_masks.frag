#version 330 core
// mrr-effect's a-posteriori refinement of level ℓ's masks (SPEC §12.2 step 2), mirrors
// cpu_ref/effect_masks.cpp refineMasks. One pass per step, at level ℓ's size; the host
// (gpu/masks.cpp refineMasks) draws step 2 with masks.frag's blur, as the oracle calls blurMask,
// and knowing where the marks are, draws step 1 over M_ℓ's blocks and theirs, steps 2–3 within
// r_ℓ of the marks' blocks onto copies of a_ℓ and S_ℓ (the same bits as the whole level):
//   STEP 1 M_ℓ ∨= the marks (R8): `source` is M_ℓ as the blur read it (channel SOURCE_CHANNEL:
//     E's for an unwidened level 0; M'_ℓ after SPEC §13's limit), `marks` the limited marks
//   STEP 2 a_ℓ = G(σ_ℓ²) ∗ M_ℓ again: masks.frag STEP 2, along x then y, clamp-to-edge
//   STEP 3 S_ℓ ∨= [a_ℓ > 0] (R8): what the closure gave S_ℓ from finer levels is kept;
//     WITH_READ (a level mrr-effect's trim cut, SPEC §12.5): then S_ℓ ∧= D_ℓ (`read`)
layout(location = 0) out vec4 result;
uniform sampler2D source;  // step 1: M_ℓ; step 3: S_ℓ before the refinement
#if STEP == 1
uniform sampler2D marks;   // the a-posteriori marks at level ℓ (refinement_marks.frag)
#else
uniform sampler2D alpha;   // the refined a_ℓ
#endif
#ifdef WITH_READ
uniform sampler2D read;    // D_ℓ, the level pixels the blend reads (trim.frag)
#endif

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  float value = 0.0;
#if STEP == 1
  // 1. M_ℓ ∨= marks
  value = max(texelFetch(source, p, 0)[SOURCE_CHANNEL] > 0.5 ? 1.0 : 0.0, texelFetch(marks, p, 0).r);
#else
  // 3. S_ℓ ∨= [a_ℓ > 0]
  value = texelFetch(source, p, 0).r > 0.5 || texelFetch(alpha, p, 0).r > 0.0 ? 1.0 : 0.0;
#ifdef WITH_READ
  // 4. S_ℓ ∧= D_ℓ
  if (texelFetch(read, p, 0).r < 0.5) value = 0.0;
#endif
#endif
  result = vec4(value, 0.0, 0.0, 1.0);
}
