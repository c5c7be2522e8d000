#version 330 core
// The peers (SPEC §9), mirrors cpu_ref/peers.cpp. One file, three variants (host defines):
//   TILE_MASKS     tiles' stage 3, steps chosen by `step` (like masks.frag):
//                    1 a tile holds an edge: max of E over its 16×16 pixels (one fragment per tile)
//                    2 the rate: 0 on edge tiles, 1 beside one (8-neighbourhood), 2 elsewhere
//                    3 per level ℓ: S_ℓ = [rate == ℓ, inside W×H] in r, M_ℓ = rate in g, a_ℓ = S_ℓ in b
//                    4 SPEC §13 step 6 (limitTileRates): rate = max(rate, min(2, ℓ_min at the tile's
//                      centre pixel (16 t + 8), clamped to the grid))
//   COMPOSE        stage 5 at full res W×H: the final value and the level it came from;
//                  with JOINT_BILATERAL (uniform-k) the joint bilateral upsampling of c_k,
//                  else (tiles) the coarse pixel's value broadcast to its block
//   LEVEL_STAGES   stage 5 kept per level (--stages, probe, compare): ĉ_ℓ, α_ℓ and c'_ℓ as the
//                  oracle's hard switch, from the composed value and level map
// kTileSize (full-res pixels per tile side): common/shader_constants.h

#ifdef TILE_MASKS
uniform int step;
uniform sampler2D source;  // step 1: E (padded full res); 2: the tiles' edge flags; 3: the rates
uniform int sourceChannel; // step 1: E's channel in the edge target
uniform int level;         // step 3: ℓ
uniform int perTile;       // step 3: level-ℓ pixels per tile side, 16 / s_ℓ
uniform ivec2 extent;      // step 3: the level-ℓ pixels whose block starts inside W×H
uniform sampler2D limit;   // step 4: limit.frag's output, ℓ_min in a (padded full res)
layout(location = 0) out vec4 result;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  if (step == 1) {
    // 1. a tile holds an edge: max over its 16×16 pixels of E (tiles past the grid are clipped)
    ivec2 size = textureSize(source, 0);
    ivec2 lo = p * kTileSize, hi = min(lo + kTileSize, size);
    float edge = 0.0;
    for (int y = lo.y; y < hi.y; ++y)
      for (int x = lo.x; x < hi.x; ++x) edge = max(edge, texelFetch(source, ivec2(x, y), 0)[sourceChannel]);
    result = vec4(edge, 0.0, 0.0, 1.0);
  } else if (step == 2) {
    // 2. rate 0 on edge tiles, 1 beside one (8-neighbourhood), 2 elsewhere
    ivec2 last = textureSize(source, 0) - 1;
    float near = 0.0;
    for (int j = max(p.y - 1, 0); j <= min(p.y + 1, last.y); ++j)
      for (int i = max(p.x - 1, 0); i <= min(p.x + 1, last.x); ++i) near = max(near, texelFetch(source, ivec2(i, j), 0).r);
    float rate = texelFetch(source, p, 0).r > 0.5 ? 0.0 : near > 0.5 ? 1.0 : 2.0;
    result = vec4(rate, 0.0, 0.0, 1.0);
  } else if (step == 3) {
    // tileMasks: S_ℓ = a_ℓ = [rate == ℓ and inside W×H]; M_ℓ = the rate of the pixel's tile
    float rate = texelFetch(source, p / perTile, 0).r;
    bool shade = int(rate + 0.5) == level && all(lessThan(p, extent));
    float s = shade ? 1.0 : 0.0;
    result = vec4(s, rate, s, 1.0);
  } else {
    // limitTileRates: the eye's and motion's limit at the tile's centre pixel, at most 2
    ivec2 centre = min(p * kTileSize + kTileSize / 2, textureSize(limit, 0) - 1);
    float eye = min(2.0, texelFetch(limit, centre, 0).a);
    result = vec4(max(texelFetch(source, p, 0).r, eye), 0.0, 0.0, 1.0);
  }
}
#endif

#ifdef COMPOSE
layout(location = 0) out vec4 finalOut;  // the final value (rgb)
layout(location = 1) out vec4 levelOut;  // the level it came from (r)

#ifdef JOINT_BILATERAL
#include "bilateral.glsl"

uniform sampler2D sub;                // c_k at level k (rgb)
uniform sampler2D coarsePositionHit;  // level k's G-buffer
uniform sampler2D coarseNormalDepth;
uniform sampler2D fullPositionHit;    // level 0's G-buffer: the guide
uniform sampler2D fullNormalDepth;
uniform int level;                    // k
uniform int scale;                    // s_k
uniform float sigmaDepth;             // Constants::Bilateral, as the blur
uniform float normalPower;

// The weight of tap q for full-res pixel p (cpu_ref/peers.cpp: jointBilateralWeight).
float jointBilateralWeight(float b, bool hitP, float zp, vec3 np, bool hitQ, float zq, vec3 nq) {
  if (hitP != hitQ) return 0.0;  // geometry never takes background's value, nor the reverse
  if (!hitP) return b;
  // 1. depth similarity, relative to p's depth
  float dz = (zq - zp) / (sigmaDepth * zp);
  // 2. normal similarity (the bilateral blur's, SPEC §4)
  float cosine = max(dot(np, nq), 0.0);
  // 3. b_q × depth × normal
  return b * exp(-dz * dz) * normalSimilarity(cosine, normalPower);
}

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 last = textureSize(sub, 0) - 1;
  // the 4 bilinear taps of cpu_ref/blend.cpp: bilinearTaps: u = (p − ⌊s/2⌋)/s, clamped to the grid
  vec2 u = vec2(p - scale / 2) / float(scale);
  vec2 f = floor(u);
  vec2 t = u - f;
  ivec2 base = ivec2(f);
  bool hitP = texelFetch(fullPositionHit, p, 0).w > 0.5;
  vec4 guide = texelFetch(fullNormalDepth, p, 0);
  ivec2 taps[4];
  float b[4], weights[4];
  float sum = 0.0;
  int nearest = 0;
  for (int k = 0; k < 4; ++k) {
    ivec2 o = ivec2(k & 1, k >> 1);
    taps[k] = clamp(base + o, ivec2(0), last);
    b[k] = (o.x == 1 ? t.x : 1.0 - t.x) * (o.y == 1 ? t.y : 1.0 - t.y);
    vec4 q = texelFetch(coarseNormalDepth, taps[k], 0);
    bool hitQ = texelFetch(coarsePositionHit, taps[k], 0).w > 0.5;
    weights[k] = jointBilateralWeight(b[k], hitP, guide.w, guide.xyz, hitQ, q.w, q.xyz);
    sum += weights[k];
    if (b[k] > b[nearest]) nearest = k;
  }
  vec3 value = vec3(0.0);
  if (sum > 0.0) {
    // 4. normalised over the four taps
    for (int k = 0; k < 4; ++k) value += weights[k] * texelFetch(sub, taps[k], 0).rgb;
    value /= sum;
  } else {
    // 5. every weight vanished: the nearest tap
    value = texelFetch(sub, taps[nearest], 0).rgb;
  }
  finalOut = vec4(value, 1.0);
  levelOut = vec4(float(level), 0.0, 0.0, 1.0);
}
#else
uniform sampler2D rates;  // the tiles' rates (tile grid)
uniform sampler2D sub0;   // c_0, c_1, c_2 (GLSL 3.30 cannot index a sampler array by a variable)
uniform sampler2D sub1;
uniform sampler2D sub2;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  // the coarse pixel's value, broadcast to its block, unfiltered
  int from = int(texelFetch(rates, p / kTileSize, 0).r + 0.5);
  ivec2 q = p >> from;
  vec3 value = from == 0 ? texelFetch(sub0, q, 0).rgb : from == 1 ? texelFetch(sub1, q, 0).rgb : texelFetch(sub2, q, 0).rgb;
  finalOut = vec4(value, 1.0);
  levelOut = vec4(float(from), 0.0, 0.0, 1.0);
}
#endif
#endif

#ifdef LEVEL_STAGES
uniform sampler2D composed;  // COMPOSE's final value
uniform sampler2D levelMap;  // COMPOSE's level map
uniform int level;           // ℓ
layout(location = 0) out vec4 cHat;
layout(location = 1) out vec4 alphaOut;
layout(location = 2) out vec4 composite;

void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  int from = int(texelFetch(levelMap, p, 0).r + 0.5);
  vec3 value = texelFetch(composed, p, 0).rgb;
  // ĉ_ℓ, α_ℓ and c'_ℓ as a hard switch: the supplying level has α = 1, the others 0
  cHat = vec4(level == from ? value : vec3(0.0), 1.0);
  alphaOut = vec4(level == from ? 1.0 : 0.0, 0.0, 0.0, 1.0);
  composite = vec4(level <= from ? value : vec3(0.0), 1.0);
}
#endif
