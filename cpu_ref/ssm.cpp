#include "cpu_ref/ssm.h"


#include <algorithm>
#include <cmath>

#include "common/parallel.h"
#include "common/shader_constants.h"  // kMaxSearchTexels
#include "cpu_ref/stencil.h"

namespace mrr {

namespace {
// Offset of tap i of an n-tap regular grid spanning [−half, half] (texel centres of the grid).
float gridOffset(int i, int n, float half) { return gridTapFactor(i, n) * half; }

// Penumbra width of a directional light of angular diameter θ (Fernando 2005, adapted to
// parallel light): (d_receiver − d_blocker) · 2 tan(θ/2).
float penumbraWidth(float receiverDepth, float blockerDepth, float tanHalfAngle) {
  return (receiverDepth - blockerDepth) * 2.0f * tanHalfAngle;
}

// Step 1 of ssmAt: the blocker search over a blockerGrid² grid spanning the widest penumbra a
// blocker at the light plane could cast. Fills d's searchTexels, searchTaps and blockers;
// returns the blockers' summed depth.
float blockerSearch(const ShadowMap& map, const Receiver& r, const Constants::Ssm& ssm, SsmDetail& d) {
  d.searchTexels = std::clamp(r.depth * ssm.tanHalfAngle / map.texel, 0.5f, kMaxSearchTexels);
  float blockerSum = 0.0f;
  for (int j = 0; j < ssm.blockerGrid; ++j)
    for (int i = 0; i < ssm.blockerGrid; ++i) {
      const float du = gridOffset(i, ssm.blockerGrid, d.searchTexels);
      const float dv = gridOffset(j, ssm.blockerGrid, d.searchTexels);
      const float b = map.depthAt(r.u + du, r.v + dv);
      ++d.searchTaps;
      if (b < receiverDepthAt(r, du, dv)) {
        blockerSum += b;
        ++d.blockers;
      }
    }
  return blockerSum;
}

// What pixel (x, y) pays (common/shader_constants.h): kPcfSampleNone facing away from the light (V = 0 at
// once), kPcfSampleSearch facing it with no blocker found (the search alone; also off geometry,
// where the block's pixels on geometry are assumed to search), kPcfSamplePcf where the search
// finds a blocker (SsmDetail's pcfTaps > 0, without the PCF); where it searches on geometry, with
// its map footprint in the high bits.
uint8_t pcfSampleAt(const GBuffer& g, const ShadowMap& map, const View& view, const Constants::Ssm& ssm, int x, int y) {
  if (!g.hit.at(x, y)) return kPcfSampleSearch;
  const Receiver r = receiverAt(map, view.toWorld(g.positionAt(x, y)), view.directionToWorld(g.normalAt(x, y)),
                                ssm.biasTexels);
  if (!r.facesLight) return kPcfSampleNone;
  SsmDetail d;
  blockerSearch(map, r, ssm, d);
  const uint8_t paid = d.blockers > 0 ? kPcfSamplePcf : kPcfSampleSearch;
  return static_cast<uint8_t>(paid | (footprintSteps(mapFootprintAt(g, map, view, ssm.biasTexels, x, y, r)) << kPcfSampleClassBits));
}
}  // namespace

float mapFootprintAt(const GBuffer& g, const ShadowMap& map, const View& view, float biasTexels, int x, int y,
                     const Receiver& r) {
  float sum = 0.0f;
  int axes = 0;
  for (const glm::ivec2 axis : {glm::ivec2(1, 0), glm::ivec2(0, 1)})
    for (const int sign : {1, -1}) {  // 1. the next pixel along the axis, else the previous
      const glm::ivec2 q = glm::ivec2(x, y) + sign * axis;
      if (q.x < 0 || q.y < 0 || q.x >= g.width || q.y >= g.height || !g.hit.at(q.x, q.y)) continue;
      // 2. how far its receiver lies from this one on the map, in texels
      const Receiver n = receiverAt(map, view.toWorld(g.positionAt(q.x, q.y)), view.directionToWorld(g.normalAt(q.x, q.y)),
                                    biasTexels);
      const float du = n.u - r.u, dv = n.v - r.v;
      sum += std::sqrt(du * du + dv * dv);
      ++axes;
      break;
    }
  return axes > 0 ? sum / static_cast<float>(axes) : 0.0f;  // 3. the mean over the axes found
}

int footprintSteps(float texels) {
  return static_cast<int>(std::min(kMaxFootprintTexels, texels) * kFootprintSteps + 0.5f);
}

float ssmAt(const GBuffer& g, const ShadowMap& map, const View& view, const Constants::Ssm& ssm, int x, int y,
            SsmDetail* detail) {
  if (!g.hit.at(x, y)) return 1.0f;
  const Receiver r = receiverAt(map, view.toWorld(g.positionAt(x, y)), view.directionToWorld(g.normalAt(x, y)),
                                ssm.biasTexels);
  SsmDetail d;
  d.receiverDepth = r.depth;
  d.facesLight = r.facesLight;
  if (!r.facesLight) {  // the visible side faces away from the light: in its own shadow
    if (detail) *detail = d;
    return 0.0f;
  }
  // 1. blocker search: the widest penumbra a blocker at the light plane could cast
  const float blockerSum = blockerSearch(map, r, ssm, d);
  if (d.blockers == 0) {  // nothing in front anywhere in the search region: fully lit
    if (detail) *detail = d;
    return 1.0f;
  }
  d.blockerDepth = blockerSum / static_cast<float>(d.blockers);
  // 2. penumbra width from the receiver and mean blocker depths
  d.penumbraWorld = penumbraWidth(r.depth, d.blockerDepth, ssm.tanHalfAngle);
  d.filterTexels = std::clamp(0.5f * d.penumbraWorld / map.texel, 0.5f, kMaxSearchTexels);
  // 3. PCF over an n×n grid: the fraction of taps that see the light
  for (int j = 0; j < ssm.grid; ++j)
    for (int i = 0; i < ssm.grid; ++i) {
      const float du = gridOffset(i, ssm.grid, d.filterTexels);
      const float dv = gridOffset(j, ssm.grid, d.filterTexels);
      d.litTaps += receiverDepthAt(r, du, dv) <= map.depthAt(r.u + du, r.v + dv);
    }
  d.pcfTaps = ssm.grid * ssm.grid;
  if (detail) *detail = d;
  return static_cast<float>(d.litTaps) / static_cast<float>(d.pcfTaps);
}

ImageU8 pcfSample(const GBuffer& g, const ShadowMap& map, const View& view, const Constants::Ssm& ssm) {
  const int w = (g.width + kPcfSampleStep - 1) / kPcfSampleStep, h = (g.height + kPcfSampleStep - 1) / kPcfSampleStep;
  ImageU8 sample(w, h, 1, 0);
  parallelFor(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y)
      for (int x = 0; x < w; ++x)
        sample.at(x, y) = pcfSampleAt(g, map, view, ssm, std::min(x * kPcfSampleStep + kPcfSampleStep / 2, g.width - 1),
                                      std::min(y * kPcfSampleStep + kPcfSampleStep / 2, g.height - 1));
  });
  return sample;
}

ImageF renderSsm(const GBuffer& g, const ShadowMap& map, const ImageU8& stencil, const View& view,
                 const Constants::Ssm& ssm) {
  ImageF out(g.width, g.height, 1, 0.0f);
  forEachStencilled(stencil, [&](int x, int y) { out.at(x, y) = ssmAt(g, map, view, ssm, x, y); });
  return out;
}

}  // namespace mrr
