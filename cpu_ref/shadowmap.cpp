#include "cpu_ref/shadowmap.h"

#include "common/parallel.h"

#include <algorithm>
#include <cmath>

#include "cpu_ref/rays.h"

namespace mrr {

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
  // 1. normal offset and a constant depth bias, both in texels: they cover the depth the
  //    receiver's plane changes by between a tap and the centre of the texel holding it
  const float bias = biasTexels * map.texel;
  const glm::vec3 l = map.lightCoordinates(worldPosition + worldNormal * bias);
  Receiver r;
  r.u = l.x;
  r.v = l.y;
  r.depth = l.z - bias;
  // 2. which side of the surface the light is on (forward is the way the light travels)
  const float nForward = glm::dot(worldNormal, map.forward);
  r.facesLight = nForward < 0.0f;
  // 3. the tangent plane's depth slope per texel: n·(du right + dv up) texel + n·forward dd = 0,
  //    with |n·forward| capped near grazing (kReceiverMinCosine)
  const float cosine = std::min(nForward, -kReceiverMinCosine);
  r.slopeU = -glm::dot(worldNormal, map.right) / cosine * map.texel;
  r.slopeV = -glm::dot(worldNormal, map.up) / cosine * map.texel;
  return r;
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
