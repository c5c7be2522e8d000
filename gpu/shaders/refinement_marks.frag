#version 330 core
// mrr-effect's a-posteriori marks (SPEC §12.2 step 1), mirrors cpu_ref/effect_masks.cpp
// refinementMarks. One pass per step; the host compiles a variant per pass shape
// (gpu/effect_masks.cpp drawRefinementMarks): STEP, CHANNELS and RATIO are constants.
//   STEP 1 at the next coarser enabled level n's size (R8): [v(q) > τ], v(q) the largest over the
//     CHANNELS channels of max − min of c_n over q's 3×3 neighbourhood of shaded (S_n = 1) hit
//     pixels, q itself such a pixel (else no mark); outside the level nothing is read
//   STEP 2 at the finer level ℓ's size (R8): each pixel p takes its parent's mark,
//     at (min(⌊p_x / RATIO⌋, w_n − 1), min(⌊p_y / RATIO⌋, h_n − 1)), RATIO = 2^{n−ℓ}
// SPEC §13's level limit is then masks.frag STEP 5 on these marks, as the oracle's applyLevelLimit.
layout(location = 0) out vec4 result;
uniform sampler2D source;  // step 1: c_n (its first CHANNELS channels); step 2: step 1's marks

#if STEP == 1
uniform sampler2D stencil;      // S_n
uniform sampler2D positionHit;  // level n's G-buffer: view position, hit in .w
uniform float tau;              // τ_v

bool shadedHit(ivec2 q) { return texelFetch(stencil, q, 0).r > 0.5 && texelFetch(positionHit, q, 0).w > 0.5; }
#endif

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(source, 0);
  float marked = 0.0;
#if STEP == 1
  // 1. v(q) > τ at each coarser pixel q, over the shaded hit pixels of its 3×3 neighbourhood
  if (shadedHit(p)) {
    vec4 centre = texelFetch(source, p, 0);
    float range = 0.0;
    for (int ch = 0; ch < CHANNELS; ++ch) {
      float lo = centre[ch], hi = lo;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          ivec2 q = p + ivec2(dx, dy);
          if (q.x < 0 || q.y < 0 || q.x >= size.x || q.y >= size.y || !shadedHit(q)) continue;
          float v = texelFetch(source, q, 0)[ch];
          lo = min(lo, v);
          hi = max(hi, v);
        }
      range = max(range, hi - lo);
    }
    marked = range > tau ? 1.0 : 0.0;
  }
#else
  // 2. each finer pixel takes its coarser parent's mark
  marked = texelFetch(source, min(p / RATIO, size - 1), 0).r;
#endif
  result = vec4(marked, 0.0, 0.0, 1.0);
}
