#include "cpu_ref/shadowmap.h"

#include "common/parallel.h"

#include <algorithm>
#include <cmath>

#include "cpu_ref/rays.h"

namespace mrr {

ShadowMap shadowMapFrame(const DirectionalLight& light, const Bounds& bounds, int size) {
  ShadowMap m;
  m.size = size;
  // 1. light basis: forward along the light, right/up spanning the light plane
  m.forward = glm::normalize(light.direction);
  const glm::vec3 reference = std::fabs(m.forward.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  m.right = glm::normalize(glm::cross(m.forward, reference));
  m.up = glm::cross(m.right, m.forward);
  // 2. fit a square to the bounds' eight corners seen from the light
  glm::vec3 lo(3.0e38f), hi(-3.0e38f);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner((i & 1) ? bounds.hi.x : bounds.lo.x, (i & 2) ? bounds.hi.y : bounds.lo.y,
                           (i & 4) ? bounds.hi.z : bounds.lo.z);
    const glm::vec3 l(glm::dot(corner, m.right), glm::dot(corner, m.up), glm::dot(corner, m.forward));
    lo = glm::min(lo, l);
    hi = glm::max(hi, l);
  }
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 1.001f;
  const float margin = 0.01f * extent;
  m.texel = extent / static_cast<float>(size);
  const float u0 = 0.5f * (lo.x + hi.x) - 0.5f * extent, v0 = 0.5f * (lo.y + hi.y) - 0.5f * extent;
  m.origin = m.right * u0 + m.up * v0 + m.forward * (lo.z - margin);
  m.farDepth = (hi.z - lo.z) + 2.0f * margin;  // every hit lies in [margin, hi.z − lo.z + margin]
  return m;
}

ShadowMap renderShadowMap(const RayScene& rays, const DirectionalLight& light, const Bounds& bounds, int size) {
  ShadowMap m = shadowMapFrame(light, bounds, size);
  // 3. one ray per texel centre, from the light plane along the light
  m.depth = ImageF(size, size, 1, ShadowMap::kNoBlocker);
  castGrid(
      rays.handle(), size, size,
      [&](int x, int y, glm::vec3& origin, glm::vec3& direction) {
        origin = m.origin + m.right * ((static_cast<float>(x) + 0.5f) * m.texel) +
                 m.up * ((static_cast<float>(y) + 0.5f) * m.texel);
        direction = m.forward;
      },
      [&](int x, int y, const RayHit& hit) {
        if (hit.geomID != RTC_INVALID_GEOMETRY_ID) m.depth.at(x, y) = hit.t;
      });
  return m;
}

Receiver receiverAt(const ShadowMap& map, const glm::vec3& worldPosition, const glm::vec3& worldNormal,
                    float biasTexels) {
  // Normal offset and a constant depth bias, both in texels: they keep a lit surface from
  // shadowing itself through the map's finite resolution.
  const float bias = biasTexels * map.texel;
  const glm::vec3 l = map.lightCoordinates(worldPosition + worldNormal * bias);
  return {l.x, l.y, l.z - bias};
}

ImageU8 shadowTestImage(const GBuffer& g, const ShadowMap& map, const View& view, float biasTexels) {
  ImageU8 lit(g.width, g.height, 1, 1);
  parallelFor(0, g.height, [&](int y) {
    for (int x = 0; x < g.width; ++x) {
      if (!g.hit.at(x, y)) continue;
      const Receiver r =
          receiverAt(map, view.toWorld(g.positionAt(x, y)), view.directionToWorld(g.normalAt(x, y)), biasTexels);
      lit.at(x, y) = static_cast<uint8_t>(shadowTest(map, r));
    }
  });
  return lit;
}

}  // namespace mrr
