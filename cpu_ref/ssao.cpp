#include "cpu_ref/ssao.h"

#include "common/parallel.h"

#include <algorithm>
#include <cmath>

#include "common/shader_constants.h"
#include "cpu_ref/hemisphere.h"
#include "cpu_ref/stencil.h"

namespace mrr {

namespace {

// GLSL's smoothstep(0, 1, x).
float smoothstep01(float x) {
  const float t = std::clamp(x, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// SPEC §6 range check: an occluder much farther from the receiver than R counts less.
float rangeCheck(float radius, float receiverDepth, float bufferDepth) {
  const float distance = std::fabs(receiverDepth - bufferDepth);
  // Within R the ratio is ≥ 1 and smoothstep gives exactly 1: skip the division (the common
  // case at creases, where most occluders are near).
  if (distance <= radius) return 1.0f;
  return smoothstep01(radius / distance);
}

// Depth of the occluder seen along the sample's view ray: the ray meets the tangent plane of
// the texel it projects to (normal N_t, offset N_t·P_t). On a plane this is exact at any
// level, where the texel-centre depth alone is off by up to half a texel of slope and makes
// coarse levels occlude themselves (docs/method.md, "tangent-plane depth"). Rays within
// ~6° of grazing fall back to the texel-centre depth.
float occluderDepth(const glm::vec3& sample, const OccluderPlane& plane, float texelDepth, bool tangentPlane) {
  if (!tangentPlane) return texelDepth;  // the classic depth-buffer test (for comparison)
  const float along = glm::dot(plane.normal, sample);
  if (along * along <= kGrazingCosine2 * glm::dot(sample, sample)) return texelDepth;
  return -sample.z * (plane.offset / along);
}
}  // namespace

OccluderPlanes occluderPlanes(const GBuffer& g) {
  OccluderPlanes planes;
  occluderPlanes(g, planes);
  return planes;
}

void occluderPlanes(const GBuffer& g, OccluderPlanes& planes) {
  planes.resize(g.depth.pixelCount());  // uninitialised: filled in parallel below
  parallelFor(0, g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      OccluderPlane& p = planes[static_cast<size_t>(y) * g.width + x];
      if (!g.hit.at(x, y)) {
        p = {glm::vec3(0.0f), 1.0f};  // background: offset > 0 marks it
      } else {
        const glm::vec3 n = g.normalAt(x, y);
        p = {n, glm::dot(n, g.positionAt(x, y))};  // ≤ 0: the normal faces the camera
      }
    }
  });
}

namespace {
// The per-pixel evaluation. With kDetail the probe's counters are kept; without, they
// compile away. Both compute the same AO bits. (A branch-free occlusion test was measured
// slower here: it evaluates the range check for every sample.)
template <bool kDetail>
float ssaoEval(const GBuffer& g, const OccluderPlanes& planes, const View& view, const LevelConstants& level,
               const Constants::Ssao& ssao, int x, int y, SsaoDetail* detail) {
  if (!g.hit.at(x, y)) return 1.0f;
  const glm::vec3 p = g.positionAt(x, y);
  const glm::vec3 n = g.normalAt(x, y);
  // 1. per-pixel rotation about the normal from the integer hash of (x, y, level)
  const SampleFrame frame = sampleFrame(n, x, y, level.index, ssao.seed);
  // 2. hemisphere samples: occluded when the occluder is in front by more than the bias
  const float invScale = 1.0f / static_cast<float>(level.scale);
  const float width = static_cast<float>(g.width), height = static_cast<float>(g.height);
  const float receiverDepth = -p.z;
  float occlusion = 0.0f;
  SsaoDetail d;
  d.samples = ssao.samples;
  d.rotation = frame.angle;
  for (const glm::vec3& k : ssao.kernel) {
    const glm::vec3 s = p + ssao.radius * frame.apply(k);
    const float sampleDepth = -s.z;
    const glm::vec2 px = view.project(s) * invScale;  // level coordinates
    if (!(sampleDepth > 0.0f && px.x >= 0.0f && px.y >= 0.0f && px.x < width && px.y < height)) {
      if constexpr (kDetail) ++d.offscreen;
      continue;
    }
    const int ix = nearestLevelTexel(px.x, invScale), iy = nearestLevelTexel(px.y, invScale);  // SPEC §0
    const size_t texel = static_cast<size_t>(iy) * g.width + ix;
    const OccluderPlane& plane = planes[texel];
    if (plane.offset > 0.0f) {  // background never occludes
      if constexpr (kDetail) ++d.background;
      continue;
    }
    const float bufferDepth = occluderDepth(s, plane, g.depth.data[texel], ssao.tangentPlaneDepth);
    if (bufferDepth < sampleDepth - ssao.bias) {
      if constexpr (kDetail) ++d.occluders;
      occlusion += rangeCheck(ssao.radius, receiverDepth, bufferDepth);
    }
  }
  if constexpr (kDetail) {
    d.occlusion = occlusion;
    *detail = d;
  }
  // 3. AO = 1 − occlusion / N
  return 1.0f - occlusion / static_cast<float>(ssao.samples);
}
}  // namespace

float ssaoAt(const GBuffer& g, const OccluderPlanes& planes, const View& view, const LevelConstants& level,
             const Constants::Ssao& ssao, int x, int y, SsaoDetail* detail) {
  return detail ? ssaoEval<true>(g, planes, view, level, ssao, x, y, detail)
                : ssaoEval<false>(g, planes, view, level, ssao, x, y, nullptr);
}

ImageF renderSsao(const GBuffer& g, const OccluderPlanes& planes, const ImageU8& stencil, const View& view,
                  const LevelConstants& level, const Constants::Ssao& ssao,
                  const std::function<void(double)>& onProgress) {
  ImageF out(g.width, g.height, 1, 0.0f);
  forEachStencilled(
      stencil, [&](int x, int y) { out.at(x, y) = ssaoAt(g, planes, view, level, ssao, x, y); }, onProgress);
  return out;
}

}  // namespace mrr
