#version 330 core
// The never-slower rule's counts (SPEC §11) and the frame's shaded-pixel counts, per 8×8 block
// of the padded full-res grid (one fragment a block), as RGBA32UI counts that gpu/counts.cpp
// sums: common/frame.cpp's countHits, countEdgeSample, countForRule and countShadedPixels,
// count for count (tests/gpu/rule_counts_test.cpp holds them equal). One pass per step:
//   STEP 1 hits (countHits): in W×H, H, H_a, H_p and F (counts0); B_0..B_3, the pixels and the
//     2×2, 4×4 and 8×8 blocks holding a silhouette pixel (counts1); the block's hit pixels over
//     the padded grid, Ê: it holds a silhouette pixel or (WITH_SAMPLE) its diagonal an edge, and
//     its 64 hit bits, rows 0–3 in z and 4–7 in w, 8 a row, column i at bit i (counts2). A row of
//     the block and its border is 10 bits, so a pixel's 4-neighbours are shifts. WITH_SAMPLE
//     tests SPEC §2's edge at the block's 8 diagonal pixels (the edge sample, countEdgeSample;
//     edges.frag EDGE_SAMPLE draws the same for --stages), whose texels lie in the rows the pass
//     reads anyway.
//   STEP 2 reach (countEdgeSample): per level ℓ < 3, R_ℓ: Ê within reachBlocks[ℓ] blocks (the
//     union of the finer levels' boxes); counts0 (Ê, R_0, R_1, R_2), counts1 (the hit pixels of
//     R_0, R_1, R_2)
//   STEP 3 stencils (countForRule): per level ℓ of `counted`, |S_ℓ|, |S_ℓ ∩ hit|, |S_ℓ ∩ hit ∩
//     searched|, |S_ℓ ∩ hit ∩ pcf| over the block's level-ℓ pixels (counts0..3); WITH_HIT_BITS:
//     the hits from step 1's bits of the block (every sample pixel lies in it), else normalDepth
//   STEP 4 shaded (countShadedPixels, countHitPixels), one fragment per 4×2 block of level
//     LEVEL's grid: |S_ℓ|, the block holds any (0/1), |S_ℓ ∩ hit| (counts0)
// A full-res pixel is on geometry where its depth is > 0 (edge_test.glsl isHit, on level 0's
// G-buffer normalDepth, padded full res); a level-ℓ pixel q where the full-res pixel it samples,
// q s + s/2, is (SPEC §0, levelPixelHit); a full-res pixel pays what its 8×8 block's PCF sample
// says (pcfSampleValue).
#include "edge_test.glsl"  // normalDepth, isHit; step 1 WITH_SAMPLE: SPEC §2's test
#if STEP == 3 && WITH_HIT_BITS
uniform usampler2D hitBits;     // step 1's counts2: each block's 64 hit bits in z, w
#endif
#if WITH_PCF
uniform sampler2D pcfSample;    // SSM: what PCSS pays per 8×8 block, the byte / 255 (ssm.frag PCF_SAMPLE)
#endif
layout(location = 0) out uvec4 counts0;
#if STEP == 1 || STEP == 2 || STEP == 3
layout(location = 1) out uvec4 counts1;
#endif
#if STEP == 1 || STEP == 3
layout(location = 2) out uvec4 counts2;
#endif
#if STEP == 3
layout(location = 3) out uvec4 counts3;
#endif

#if (STEP == 3 && !WITH_HIT_BITS) || STEP == 4
bool hitAt(ivec2 q) { return isHit(texelFetch(normalDepth, q, 0)); }
#endif

// What a pixel on geometry of block b pays: its class (kPcfSample…) and map footprint steps.
ivec2 pays(ivec2 b) {
#if WITH_PCF
  int v = int(texelFetch(pcfSample, min(b, textureSize(pcfSample, 0) - 1), 0).r * 255.0 + 0.5);
  return ivec2(v & 3, v >> int(kPcfSampleClassBits));
#else
  return ivec2(int(kPcfSampleSearch), 0);  // without a sample every pixel on geometry searches
#endif
}

#if STEP == 1
uniform ivec2 frame;  // W×H
// 10 hit flags of row y as bits (bit i: column o.x − 1 + i), clamped to the image: a 4-neighbour
// outside it is the pixel itself, as countHits takes it
uint rowBits(ivec2 o, int y, ivec2 last) {
  int yc = clamp(y, 0, last.y);
  uint bits = 0u;
  for (int i = 0; i < 10; ++i)
    bits |= isHit(texelFetch(normalDepth, ivec2(clamp(o.x - 1 + i, 0, last.x), yc), 0)) ? 1u << uint(i) : 0u;
  return bits;
}
uint ones(uint v) {  // the set bits of v (GLSL 3.30 has no bitCount)
  v = v - ((v >> 1) & 0x55555555u);
  v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
  return (((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24;
}
void main() {
  ivec2 b = ivec2(gl_FragCoord.xy), o = b * 8, last = textureSize(normalDepth, 0) - 1;
  uint inW = (1u << uint(clamp(frame.x - o.x, 0, 8))) - 1u;  // the block's columns inside W, bits 0–7
  uint hits = 0u, padded = 0u, b0 = 0u, b1 = 0u, b2 = 0u;
  uint pair = 0u, quad0 = 0u, quad1 = 0u;  // silhouette bits OR-ed over row pairs and row quads
  uint up = rowBits(o, o.y - 1, last), cur = rowBits(o, o.y, last);
  uvec2 blockBits = uvec2(0u);  // rows 0–3, rows 4–7
  bool diagonalEdge = false;    // E at a diagonal pixel (WITH_SAMPLE)
  for (int j = 0; j < 8; ++j) {
    uint down = rowBits(o, o.y + j + 1, last);
#if WITH_SAMPLE
    // the edge sample: E at the diagonal pixel (j, j); its five texels are in the rows just read
    ivec2 q = o + ivec2(j);
    diagonalEdge = diagonalEdge || (inside(q, last + 1) && anyKind(edgeAt(q, last + 1)));
#endif
    uint row = (cur >> 1) & 0xFFu;  // the block's 8 columns
    if (j < 4) blockBits.x |= row << uint(8 * j); else blockBits.y |= row << uint(8 * (j - 4));
    padded += ones(row);
    bool inH = o.y + j < frame.y;
    // a pixel on geometry with a 4-neighbour off it (in W×H)
    uint silhouette = inH ? (cur & ~((cur << 1) & (cur >> 1) & up & down)) >> 1 & 0xFFu & inW : 0u;
    hits += inH ? ones(row & inW) : 0u;
    b0 += ones(silhouette);
    pair |= silhouette;
    if ((j & 1) == 1) {  // B_1: the 2×2 sub-blocks holding one
      b1 += ones((pair | (pair >> 1)) & 0x55u);
      if (j < 4) quad0 |= pair; else quad1 |= pair;
      pair = 0u;
    }
    up = cur;
    cur = down;
  }
  b2 = ones((quad0 | quad0 >> 1 | quad0 >> 2 | quad0 >> 3) & 0x11u) + ones((quad1 | quad1 >> 1 | quad1 >> 2 | quad1 >> 3) & 0x11u);
  bool any3 = (quad0 | quad1) != 0u;
  ivec2 paid = pays(b);
  uint searched = paid.x != int(kPcfSampleNone) ? hits : 0u;
  uint pcf = paid.x == int(kPcfSamplePcf) ? hits : 0u;
#if WITH_PCF
  uint footprint = searched * uint(paid.y);
#else
  uint footprint = 0u;  // F without a sample: none
#endif
  // Ê for step 2: a silhouette block, or (with the sample) one whose diagonal holds an edge
  bool sampled = any3 || diagonalEdge;
  counts0 = uvec4(hits, searched, pcf, footprint);
  counts1 = uvec4(b0, b1, b2, any3 ? 1u : 0u);
  counts2 = uvec4(padded, sampled ? 1u : 0u, blockBits);
}
#elif STEP == 2
uniform usampler2D hits;     // STEP 1's counts2: hit pixels over the padded grid, Ê
uniform ivec3 reachBlocks;   // per level ℓ < 3: the box R_ℓ spans, in blocks; -1: not counted
void main() {
  ivec2 b = ivec2(gl_FragCoord.xy), last = textureSize(hits, 0) - 1;
  int widest = max(reachBlocks.x, max(reachBlocks.y, reachBlocks.z));
  bvec3 reached = bvec3(false);
  for (int j = -widest; j <= widest; ++j)
    for (int i = -widest; i <= widest; ++i) {
      ivec2 q = b + ivec2(i, j);
      if (any(lessThan(q, ivec2(0))) || any(greaterThan(q, last)) || texelFetch(hits, q, 0).y == 0u) continue;
      int d = max(abs(i), abs(j));
      reached = bvec3(reached.x || d <= reachBlocks.x, reached.y || d <= reachBlocks.y, reached.z || d <= reachBlocks.z);
    }
  uvec2 own = texelFetch(hits, b, 0).xy;
  uvec3 r = uvec3(reached);
  counts0 = uvec4(own.y, r);
  counts1 = uvec4(r * own.x, 0u);
}
#elif STEP == 3
uniform sampler2D stencil0, stencil1, stencil2, stencil3;  // S_ℓ (R8)
uniform ivec4 counted;  // 1: level ℓ is enabled and shaded
#if WITH_HIT_BITS
uvec2 blockHits;  // the block's hit bits (main)
// full-res pixel p of this block (p − 8 b in 0..7 a side) on geometry
bool hitAt(ivec2 p) {
  ivec2 local = p & 7;
  uint bits = local.y < 4 ? blockHits.x : blockHits.y;
  return ((bits >> uint(8 * (local.y & 3) + local.x)) & 1u) != 0u;
}
#endif
uvec4 level(sampler2D stencil, int scale, ivec2 b, ivec2 paid) {
  int side = 8 / scale;  // level pixels per block side
  uvec4 n = uvec4(0u);
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i) {
      ivec2 q = b * side + ivec2(i, j);
      if (texelFetch(stencil, q, 0).r < 0.5) continue;
      n.x += 1u;
      if (!hitAt(q * scale + scale / 2)) continue;
      n.y += 1u;
      n.z += paid.x != int(kPcfSampleNone) ? 1u : 0u;
      n.w += paid.x == int(kPcfSamplePcf) ? 1u : 0u;
    }
  return n;
}
void main() {
  ivec2 b = ivec2(gl_FragCoord.xy), paid = pays(b);
#if WITH_HIT_BITS
  blockHits = texelFetch(hitBits, b, 0).zw;
#endif
  counts0 = counted.x != 0 ? level(stencil0, 1, b, paid) : uvec4(0u);
  counts1 = counted.y != 0 ? level(stencil1, 2, b, paid) : uvec4(0u);
  counts2 = counted.z != 0 ? level(stencil2, 4, b, paid) : uvec4(0u);
  counts3 = counted.w != 0 ? level(stencil3, 8, b, paid) : uvec4(0u);
}
#else
uniform sampler2D stencil;  // S_ℓ of level LEVEL (R8)
void main() {
  ivec2 b = ivec2(gl_FragCoord.xy), size = textureSize(stencil, 0), hitLast = textureSize(normalDepth, 0) - 1;
  const int scale = 1 << LEVEL;
  uint set = 0u, onGeometry = 0u;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 4; ++i) {
      ivec2 q = b * ivec2(4, 2) + ivec2(i, j);
      if (q.x >= size.x || q.y >= size.y || texelFetch(stencil, q, 0).r < 0.5) continue;
      set += 1u;
      onGeometry += hitAt(min(q * scale + scale / 2, hitLast)) ? 1u : 0u;
    }
  counts0 = uvec4(set, set > 0u ? 1u : 0u, onGeometry, 0u);
}
#endif
