#version 330 core
// mrr-effect's a-posteriori marks (SPEC §12.2 step 1), mirrors cpu_ref/effect_masks.cpp
// refinementMarks. One pass per step; the host compiles a variant per pass shape
// (gpu/effect_masks.cpp drawRefinementMarks): STEP, PASS, CHANNELS, RANGE_OUT and RATIO are constants.
//   STEP 1 at the next coarser enabled level n's size: v(q), the largest over the CHANNELS channels
//     of max − min of c_n over q's 3×3 neighbourhood of shaded (S_n = 1) hit pixels, q itself such
//     a pixel (else no mark, v = −1); outside the level nothing is read. Then [v(q) > τ] (R8), or
//     with RANGE_OUT v itself (R32F: SPEC §12.4's budget selects the marks on the host). Made
//     separably (localRangesSeparable): PASS 1 along x, the min (target 0) and max (target 1) of
//     each channel over the row of three, excluded pixels neutral (+inf, −inf); PASS 2 along y over
//     those. PASS 0 is the readable form over the whole 3×3 at once (localRange): the same bits.
//   STEP 2 at the finer level ℓ's size (R8): each pixel p takes its parent's mark,
//     at (min(⌊p_x / RATIO⌋, w_n − 1), min(⌊p_y / RATIO⌋, h_n − 1)), RATIO = 2^{n−ℓ}
// SPEC §13's level limit is then masks.frag STEP 5 on these marks, as the oracle's applyLevelLimit.
layout(location = 0) out vec4 result;
#if STEP == 1 && PASS == 1
layout(location = 1) out vec4 highest;
#endif
uniform sampler2D source;  // step 1: c_n (its first CHANNELS channels), or pass 2: pass 1's minima; step 2: step 1's marks

#if STEP == 1
uniform sampler2D stencil;      // S_n
uniform sampler2D positionHit;  // level n's G-buffer: view position, hit in .w
uniform float tau;              // τ_v
#if PASS == 2
uniform sampler2D maxima;       // pass 1's maxima
#endif

bool shadedHit(ivec2 q) { return texelFetch(stencil, q, 0).r > 0.5 && texelFetch(positionHit, q, 0).w > 0.5; }
float infinity() { return uintBitsToFloat(0x7f800000u); }

// v > τ, or v itself (RANGE_OUT)
vec4 decide(float range) {
#if RANGE_OUT
  return vec4(range, 0.0, 0.0, 1.0);
#else
  float marked = 0.0;
  if (range >= 0.0) marked = range > tau ? 1.0 : 0.0;
  return vec4(marked, 0.0, 0.0, 1.0);
#endif
}
#endif

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(source, 0);
#if STEP == 1 && PASS == 1
  // 1a. along x: each channel's min and max over (x − 1 .. x + 1, y), excluded pixels neutral
  vec4 lo = vec4(infinity()), hi = vec4(-infinity());
  for (int d = -1; d <= 1; ++d) {
    ivec2 q = ivec2(p.x + d, p.y);
    if (q.x < 0 || q.x >= size.x || !shadedHit(q)) continue;
    vec4 v = texelFetch(source, q, 0);
    lo = min(lo, v);
    hi = max(hi, v);
  }
  result = lo;
  highest = hi;
#elif STEP == 1 && PASS == 2
  // 1b. along y over pass 1's: v = the largest max − min over the channels, q itself a shaded hit pixel
  float range = -1.0;
  if (shadedHit(p)) {
    vec4 lo = vec4(infinity()), hi = vec4(-infinity());
    for (int d = -1; d <= 1; ++d) {
      ivec2 q = ivec2(p.x, p.y + d);
      if (q.y < 0 || q.y >= size.y) continue;
      lo = min(lo, texelFetch(source, q, 0));
      hi = max(hi, texelFetch(maxima, q, 0));
    }
    range = 0.0;
    for (int ch = 0; ch < CHANNELS; ++ch) range = max(range, hi[ch] - lo[ch]);
  }
  result = decide(range);
#elif STEP == 1
  // 1. the readable form: v(q) over the shaded hit pixels of q's whole 3×3 neighbourhood at once
  float range = -1.0;
  if (shadedHit(p)) {
    vec4 centre = texelFetch(source, p, 0);
    range = 0.0;
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
  }
  result = decide(range);
#else
  // 2. each finer pixel takes its coarser parent's mark
  result = vec4(texelFetch(source, min(p / RATIO, size - 1), 0).r, 0.0, 0.0, 1.0);
#endif
}
