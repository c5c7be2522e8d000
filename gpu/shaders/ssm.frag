#version 330 core
// Stage 4 for soft shadows — PCSS (Fernando 2005) on the light's shadow map (SPEC §6 SSM,
// docs/spec.md §6.4), mirrors cpu_ref/ssm.cpp: ssmAt. Drawn with the stencil test, so it runs
// only where S_ℓ = 1. Output: the visibility V in [0, 1].
// With PCF_SAMPLE (cpu_ref/ssm.cpp: pcfSample, SPEC §11): the never-slower rule's sample of
// where PCF is paid, drawn on a ⌈W/8⌉×⌈H/8⌉ R8 target over the level-0 G-buffer; fragment
// (x, y) asks pixel (8x + 4, 8y + 4) what it pays and writes the byte common/shader_constants.h names:
// 0 facing away from the light, 1 the blocker search alone (and sky), 2 the search and PCF; where
// it searches on geometry, plus its map footprint (cpu_ref/ssm.cpp: mapFootprintAt) in the high bits.
#include "shadowmap.glsl"
uniform sampler2D positionHit;  // level G-buffer: view position, hit
uniform sampler2D normalDepth;  // level G-buffer: view normal, depth
uniform float tanHalfAngle;     // tan(θ/2) of the light's angular diameter θ
uniform int blockerGrid;        // blocker-search taps per side
uniform int grid;               // PCF taps per side, n (N = n²)
// Tap i of an n-tap grid over [−h, h] sits at factor_i · h; the factors come from the
// host (cpu_ref/ssm.h: gridTapFactor), so both paths place every tap on the same bits.
// kMaxBlockerGrid, kMaxPcfGrid, and kMaxSearchTexels (the blocker search's half-width, and so
// the penumbra's, in map texels, at most): common/shader_constants.h
uniform float blockerFactors[kMaxBlockerGrid];
uniform float pcfFactors[kMaxPcfGrid];
layout(location = 0) out vec4 visibility;

// Ends the fragment with V = v, or under PCF_SAMPLE with what the pixel paid (the byte `paid`).
#ifdef PCF_SAMPLE
float footprintBits = 0.0;  // the byte's high bits: the footprint's steps, once the pixel searches
#define RETURN_WITHOUT_PCF(v, paid) { visibility = vec4((float(paid) + footprintBits) / 255.0); return; }
#else
#define RETURN_WITHOUT_PCF(v, paid) { visibility = v; return; }
#endif

// Offset of a tap of a regular grid spanning [−h, h] (texel centres of the grid).
float gridOffset(float factor, float halfWidth) { return factor * halfWidth; }

// Penumbra width of a directional light of angular diameter θ (Fernando 2005, adapted to
// parallel light): (d_receiver − d_blocker) · 2 tan(θ/2).
float penumbraWidth(float receiverDepth, float blockerDepth) {
  return (receiverDepth - blockerDepth) * 2.0 * tanHalfAngle;
}

#ifdef PCF_SAMPLE
// SPEC §11: the map footprint of `pixel`, whose receiver is r: how far its neighbours' receivers
// lie from r on the map, in texels, the mean over the two axes (cpu_ref/ssm.cpp: mapFootprintAt).
float mapFootprintAt(ivec2 pixel, Receiver r) {
  ivec2 size = textureSize(positionHit, 0);
  float sum = 0.0;
  int axes = 0;
  for (int a = 0; a < 2; ++a)
    for (int k = 0; k < 2; ++k) {  // 1. the next pixel along the axis, else the previous
      int sign = k == 0 ? 1 : -1;
      ivec2 q = pixel + sign * (a == 0 ? ivec2(1, 0) : ivec2(0, 1));
      if (q.x < 0 || q.y < 0 || q.x >= size.x || q.y >= size.y) continue;
      vec4 qh = texelFetch(positionHit, q, 0);
      if (qh.w < 0.5) continue;
      // 2. how far its receiver lies from this one on the map, in texels
      Receiver n = receiverAt(viewToWorld(qh.xyz), viewDirectionToWorld(texelFetch(normalDepth, q, 0).xyz));
      float du = n.u - r.u, dv = n.v - r.v;
      sum += sqrt(du * du + dv * dv);
      ++axes;
      break;
    }
  return axes > 0 ? sum / float(axes) : 0.0;  // 3. the mean over the axes found
}
#endif

void main() {
#ifdef PCF_SAMPLE
  // kPcfSample… (the step and the values): common/shader_constants.h
  const int stride = kPcfSampleStep;
  ivec2 pixel = min(ivec2(gl_FragCoord.xy) * stride + stride / 2, textureSize(positionHit, 0) - 1);
#else
  ivec2 pixel = ivec2(gl_FragCoord.xy);
#endif
  vec4 ph = texelFetch(positionHit, pixel, 0);
  if (ph.w < 0.5) RETURN_WITHOUT_PCF(vec4(1.0), kPcfSampleSearch);
  vec3 n = texelFetch(normalDepth, pixel, 0).xyz;
  Receiver r = receiverAt(viewToWorld(ph.xyz), viewDirectionToWorld(n));
  if (!r.facesLight)  // the visible side faces away from the light: in its own shadow
    RETURN_WITHOUT_PCF(vec4(0.0, 0.0, 0.0, 1.0), kPcfSampleNone);
#ifdef PCF_SAMPLE
  footprintBits = floor(min(kMaxFootprintTexels, mapFootprintAt(pixel, r)) * kFootprintSteps + 0.5) *
                  float(1 << kPcfSampleClassBits);
#endif
  // 1. blocker search: the widest penumbra a blocker at the light plane could cast
  float searchTexels = clamp(r.depth * tanHalfAngle / mapTexel, 0.5, kMaxSearchTexels);
  float blockerSum = 0.0;
  int blockers = 0;
  for (int j = 0; j < blockerGrid; ++j)
    for (int i = 0; i < blockerGrid; ++i) {
      float du = gridOffset(blockerFactors[i], searchTexels), dv = gridOffset(blockerFactors[j], searchTexels);
      float b = depthAt(r.u + du, r.v + dv);
      if (b < receiverDepthAt(r, du, dv)) {
        blockerSum += b;
        ++blockers;
      }
    }
  if (blockers == 0)  // nothing in front anywhere in the search region: fully lit
    RETURN_WITHOUT_PCF(vec4(1.0), kPcfSampleSearch);
#ifdef PCF_SAMPLE
  visibility = vec4((float(kPcfSamplePcf) + footprintBits) / 255.0);  // PCF runs here
  return;
#endif
  float blockerDepth = blockerSum / float(blockers);
  // 2. penumbra width from the receiver and mean blocker depths
  float penumbraWorld = penumbraWidth(r.depth, blockerDepth);
  float filterTexels = clamp(0.5 * penumbraWorld / mapTexel, 0.5, kMaxSearchTexels);
  // 3. PCF over an n×n grid: the fraction of taps that see the light
  int litTaps = 0;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      float du = gridOffset(pcfFactors[i], filterTexels), dv = gridOffset(pcfFactors[j], filterTexels);
      if (receiverDepthAt(r, du, dv) <= depthAt(r.u + du, r.v + dv)) ++litTaps;
    }
  visibility = vec4(float(litTaps) / float(grid * grid), 0.0, 0.0, 1.0);
}
