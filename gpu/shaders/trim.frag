#version 330 core
// mrr-effect's trim (SPEC §12.5 steps 2–3): level LEVEL shaded only where the blend reads it,
// mirrors cpu_ref/masks.cpp blendReads and trimToBlend. One pass per step; the host
// (gpu/masks.cpp trimToBlend) draws them after the closure, from blend.frag REACH's R(p):
//   STEP 1 (2a) along x, on a (level width) × (padded full-res height) target: per full-res row,
//     level column q is set where some p in [q s − s/2, q s + 3s/2) ∩ [0, W) has R(p) ≥ LEVEL
//     (`source`: R as ℓ/255); s = 2^LEVEL, so those are the pixels whose bilinear taps include q
//   STEP 2 (2b) along y, at level LEVEL's size: some row in [q s − s/2, q s + 3s/2) ∩ [0, H) set
//   STEP 3 (2c) along x: some pixel within MARGIN set (SSAO's blur radius; the host skips steps
//     3 and 4 without a margin)
//   STEP 4 (2c) along y: likewise: D_ℓ
//   STEP 5 (3) S_ℓ ∧= D_ℓ (`source` S_ℓ, `read` D_ℓ)
uniform sampler2D source;
#if STEP == 1 || STEP == 2
uniform ivec2 frame;  // W×H
#endif
#if STEP == 5
uniform sampler2D read;
#endif
layout(location = 0) out vec4 result;

bool setAt(ivec2 q) { return texelFetch(source, q, 0).r > 0.5; }

void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  const int s = 1 << LEVEL;
  bool any = false;
#if STEP == 1
  // 2a. R(p) ≥ ℓ for some p of the row in the window
  for (int px = max(0, q.x * s - s / 2); px < min(frame.x, q.x * s + 3 * s / 2); ++px)
    any = any || int(texelFetch(source, ivec2(px, q.y), 0).r * 255.0 + 0.5) >= LEVEL;
#elif STEP == 2
  // 2b. some row of the window holds one
  for (int py = max(0, q.y * s - s / 2); py < min(frame.y, q.y * s + 3 * s / 2); ++py) any = any || setAt(ivec2(q.x, py));
#elif STEP == 3 || STEP == 4
  // 2c. within MARGIN, clipped to the grid
  ivec2 last = textureSize(source, 0) - 1;
  ivec2 along = STEP == 3 ? ivec2(1, 0) : ivec2(0, 1);
  for (int i = -MARGIN; i <= MARGIN; ++i) {
    ivec2 t = q + along * i;
    if (all(greaterThanEqual(t, ivec2(0))) && all(lessThanEqual(t, last))) any = any || setAt(t);
  }
#else
  // 3. S_ℓ ∧= D_ℓ
  any = setAt(q) && texelFetch(read, q, 0).r > 0.5;
#endif
  result = vec4(any ? 1.0 : 0.0, 0.0, 0.0, 1.0);
}
