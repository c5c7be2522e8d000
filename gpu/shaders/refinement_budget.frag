#version 330 core
// mrr-effect's budgeted selection on the GPU (SPEC §12.4), mirrors common/effect_budget.cpp
// (candidatePrices, priorityKey, selectRefinement) with the same numbered steps; the host draws
// the passes (gpu/effect_masks.cpp drawBudgetedSelection) and reads nothing back. Whole numbers
// in uint32 throughout, sums held at 2^32 − 1, so every step is exact on both paths. STEP is a
// constant per pass:
//   STEP 2 at level ℓ's width × level n's height: 2a each level-ℓ pixel's price (0 where S_ℓ = 1,
//     else its class's), 2b summed down the window's rows [q_y·RATIO − r, (q_y + 1)·RATIO + r)
//   STEP 3 at level n: 2c the sum along the window's columns: the price; 3 the key (kBudgetKeys:
//     not a candidate, v(q) at most its τ). Out: (price, key, marked before, 0)
//   STEP 4 (1×1): the level's state: (threshold so far kBudgetKeys, what is left, S(threshold) 0,
//     the share = left / levelsLeft); left is the frame's budget for the first refined level, else
//     what the one before it left (its state's left − S)
//   STEP 5 at level n's blocks of FACTOR² candidates: 4a for the kBudgetRadix thresholds
//     t_j = max(0, T − (kBudgetRadix − j)·stride) below the state's T, the total price of the
//     block's candidates with a key of at least t_j (4 targets × 4 channels)
//   STEP 6 the same totals, FACTOR² blocks of them summed (to 1×1)
//   STEP 7 (1×1): 4b the least t_j whose total fits the share becomes T (with its S), else T stays
//   STEP 8 at level n (R8): 4c the marks, the candidates with a key of at least T
//   STEP 9 at level n, after the frame's clock: (candidate, marked, marked and marked before, 0),
//     for the report's counts (gpu/counts.h sums them)
#if STEP == 5 || STEP == 6
layout(location = 0) out uvec4 sums0;
layout(location = 1) out uvec4 sums1;
layout(location = 2) out uvec4 sums2;
layout(location = 3) out uvec4 sums3;
#elif STEP == 8
layout(location = 0) out vec4 result;
#else
layout(location = 0) out uvec4 result;
#endif

// a + b, held at 2^32 − 1
uint saturatingAdd(uint a, uint b) {
  uint s = a + b;
  return s < a ? 0xffffffffu : s;
}

#if STEP == 2
uniform sampler2D stencil;      // S_ℓ, a priori
uniform sampler2D positionHit;  // level 0's G-buffer: hit in .w
uniform uvec3 prices;           // paying, paying PCF, leaving (units)
uniform int levelScale;         // s_ℓ
uniform int radius;             // r_ℓ
#if PCF_SAMPLE
uniform sampler2D pcfSample;    // SSM: what PCSS pays per 8×8 block, the byte / 255
#endif
// 2a. (levelPixelHit; its class from the PCF sample at the same full-res pixel)
uint pixelPrice(ivec2 p) {
  if (texelFetch(stencil, p, 0).r > 0.5) return 0u;
  ivec2 full = min(p * levelScale + levelScale / 2, textureSize(positionHit, 0) - 1);
  if (texelFetch(positionHit, full, 0).w <= 0.5) return prices.z;
#if PCF_SAMPLE
  int v = int(texelFetch(pcfSample, min(full / kPcfSampleStep, textureSize(pcfSample, 0) - 1), 0).r * 255.0 + 0.5);
  int cls = v & ((1 << kPcfSampleClassBits) - 1);
  return cls == int(kPcfSampleNone) ? prices.z : cls == int(kPcfSamplePcf) ? prices.y : prices.x;
#else
  return prices.x;
#endif
}
#endif

#if STEP == 3
uniform usampler2D columns;    // STEP 2's sums
uniform sampler2D range;       // v(q), −1 off S_n (refinement_marks.frag RANGE_OUT)
uniform int radius;            // r_ℓ
uniform float tau;             // τ_v
#if HYSTERESIS
uniform sampler2D previous;    // SPEC §14.2: the previous frame's selection at this level
uniform float keepTau;         // (1 − h) τ_v
uniform uint bonus;            // its keys (hysteresisBonus)
#endif
// 3. priceKey and priorityKey. The top set bit of price > 0 (GLSL 4's findMSB, halving the range)
int topBit(uint v) {
  int n = 0;
  if (v >= 0x10000u) { v >>= 16; n += 16; }
  if (v >= 0x100u) { v >>= 8; n += 8; }
  if (v >= 0x10u) { v >>= 4; n += 4; }
  if (v >= 0x4u) { v >>= 2; n += 2; }
  if (v >= 0x2u) n += 1;
  return n;
}
uint priceKey(uint price) {
  int top = topBit(price);
  uint below = top >= kBudgetKeyBits ? price >> uint(top - kBudgetKeyBits) : price << uint(kBudgetKeyBits - top);
  return uint(top) * (1u << uint(kBudgetKeyBits)) + (below & ((1u << uint(kBudgetKeyBits)) - 1u));
}
uint priorityKey(float v, uint price, uint extra) {
  if (price == 0u) return uint(kBudgetKeys - 1);
  int key = int(floatBitsToUint(v) >> uint(23 - kBudgetKeyBits)) + kBudgetKeyOffset - int(priceKey(price)) + int(extra);
  return uint(clamp(key, 0, kBudgetKeys - 2));
}
#endif

#if STEP == 4
uniform int levelsLeft;
#if CHAINED
uniform usampler2D before;  // the refined level before this one: its final state
#else
uniform uint budget;        // the frame's budget (units)
#endif
#endif

#if STEP == 5 || STEP == 7
uniform usampler2D state;   // (T, left, S(T), share)
uniform int stride;         // the keys between two thresholds this round: 256, 16, 1
#endif
#if STEP == 5
uniform usampler2D candidates;  // STEP 3's
#endif
#if STEP == 6 || STEP == 7
uniform usampler2D values0;
uniform usampler2D values1;
uniform usampler2D values2;
uniform usampler2D values3;
#endif
#if STEP == 8 || STEP == 9
uniform usampler2D candidates;
uniform usampler2D state;
#endif

#if STEP == 5 || STEP == 7
// The thresholds this round tries, below T by `stride` keys each
uint threshold(uint t, int j) {
  uint down = uint((kBudgetRadix - j) * stride);
  return t >= down ? t - down : 0u;
}
#endif
#if STEP == 6 || STEP == 7
uvec4 sumTile(usampler2D values, ivec2 lo, ivec2 hi) {
  uvec4 s = uvec4(0u);
  for (int y = lo.y; y < hi.y; ++y)
    for (int x = lo.x; x < hi.x; ++x) {
      uvec4 v = texelFetch(values, ivec2(x, y), 0);
      s = uvec4(saturatingAdd(s.x, v.x), saturatingAdd(s.y, v.y), saturatingAdd(s.z, v.z), saturatingAdd(s.w, v.w));
    }
  return s;
}
#endif

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
#if STEP == 2
  // 2b. down the window's rows
  ivec2 size = textureSize(stencil, 0);
  int y0 = max(0, p.y * RATIO - radius), y1 = min(size.y, (p.y + 1) * RATIO + radius);
  uint sum = 0u;
  for (int y = y0; y < y1; ++y) sum = saturatingAdd(sum, pixelPrice(ivec2(p.x, y)));
  result = uvec4(sum, 0u, 0u, 0u);
#elif STEP == 3
  // 2c. along the window's columns: the price
  int x0 = max(0, p.x * RATIO - radius), x1 = min(textureSize(columns, 0).x, (p.x + 1) * RATIO + radius);
  uint price = 0u;
  for (int x = x0; x < x1; ++x) price = saturatingAdd(price, texelFetch(columns, ivec2(x, p.y), 0).r);
  // 3. a candidate's key
  float v = texelFetch(range, p, 0).r;
  bool before = false;
  float over = tau;
  uint extra = 0u;
#if HYSTERESIS
  before = texelFetch(previous, p, 0).r > 0.5;
  if (before) {
    over = keepTau;
    extra = bonus;
  }
#endif
  uint key = v > over ? priorityKey(v, price, extra) : uint(kBudgetKeys);
  result = uvec4(price, key, before ? 1u : 0u, 0u);
#elif STEP == 4
#if CHAINED
  uvec4 last = texelFetch(before, ivec2(0), 0);
  uint left = last.y - last.z;
#else
  uint left = budget;
#endif
  result = uvec4(uint(kBudgetKeys), left, 0u, left / uint(levelsLeft));
#elif STEP == 5
  // 4a. per threshold, the total price of the block's candidates at or above it
  uint t = texelFetch(state, ivec2(0), 0).x;
  uint s[kBudgetRadix];
  for (int j = 0; j < kBudgetRadix; ++j) s[j] = 0u;
  ivec2 size = textureSize(candidates, 0), lo = p * FACTOR, hi = min(lo + FACTOR, size);
  for (int y = lo.y; y < hi.y; ++y)
    for (int x = lo.x; x < hi.x; ++x) {
      uvec4 c = texelFetch(candidates, ivec2(x, y), 0);
      if (c.y == uint(kBudgetKeys)) continue;
      for (int j = 0; j < kBudgetRadix; ++j)
        if (c.y >= threshold(t, j)) s[j] = saturatingAdd(s[j], c.x);
    }
  sums0 = uvec4(s[0], s[1], s[2], s[3]);
  sums1 = uvec4(s[4], s[5], s[6], s[7]);
  sums2 = uvec4(s[8], s[9], s[10], s[11]);
  sums3 = uvec4(s[12], s[13], s[14], s[15]);
#elif STEP == 6
  ivec2 lo = p * FACTOR, hi = min(lo + FACTOR, textureSize(values0, 0));
  sums0 = sumTile(values0, lo, hi);
  sums1 = sumTile(values1, lo, hi);
  sums2 = sumTile(values2, lo, hi);
  sums3 = sumTile(values3, lo, hi);
#elif STEP == 7
  // 4b. the least threshold whose total fits the share (the totals fall as the threshold rises)
  uvec4 st = texelFetch(state, ivec2(0), 0);
  uvec4 quads[4] = uvec4[4](texelFetch(values0, ivec2(0), 0), texelFetch(values1, ivec2(0), 0),
                            texelFetch(values2, ivec2(0), 0), texelFetch(values3, ivec2(0), 0));
  for (int j = 0; j < kBudgetRadix; ++j) {
    uint total = quads[j / 4][j % 4];
    if (total <= st.w) {
      uint t = threshold(st.x, j);
      if (t < st.x) {
        st.x = t;
        st.z = total;
      }
      break;
    }
  }
  result = st;
#elif STEP == 8
  // 4c. marked: a candidate at or above T
  uint key = texelFetch(candidates, p, 0).y;
  uint t = texelFetch(state, ivec2(0), 0).x;
  result = vec4(key != uint(kBudgetKeys) && key >= t ? 1.0 : 0.0, 0.0, 0.0, 1.0);
#else
  uvec4 c = texelFetch(candidates, p, 0);
  uint t = texelFetch(state, ivec2(0), 0).x;
  bool candidate = c.y != uint(kBudgetKeys), marked = candidate && c.y >= t;
  result = uvec4(candidate ? 1u : 0u, marked ? 1u : 0u, marked && c.z != 0u ? 1u : 0u, 0u);
#endif
}
