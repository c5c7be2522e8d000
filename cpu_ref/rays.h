#pragma once
// Casting a grid of rays with Embree: 4×4 tiles, one 16-wide packet each (rtcIntersect16,
// coherent), tiles in parallel. Shared by the G-buffer and the shadow map.
#include <embree3/rtcore.h>
#include <tbb/blocked_range2d.h>
#include "common/parallel.h"

#include <glm/glm.hpp>

#include <limits>

namespace mrr {

struct RayHit {
  unsigned geomID = RTC_INVALID_GEOMETRY_ID;
  unsigned primID = 0;
  float u = 0.0f, v = 0.0f;  // barycentrics of vertices 1 and 2
  float t = 0.0f;            // distance along the (unnormalised) direction
};

// makeRay(x, y, origin, direction) fills one ray; onHit(x, y, hit) receives every result
// (geomID == RTC_INVALID_GEOMETRY_ID on a miss). Pixels are independent, so the result does
// not depend on the thread count.
template <class MakeRay, class OnHit>
void castGrid(RTCScene scene, int width, int height, const MakeRay& makeRay, const OnHit& onHit) {
  constexpr int kTile = 4;
  parallelFor(
      tbb::blocked_range2d<int>(0, (height + kTile - 1) / kTile, 0, (width + kTile - 1) / kTile),
      [&](const tbb::blocked_range2d<int>& r) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
        alignas(64) RTCRayHit16 packet;
        alignas(64) int valid[16];
        for (int ty = r.rows().begin(); ty != r.rows().end(); ++ty)
          for (int tx = r.cols().begin(); tx != r.cols().end(); ++tx) {
            for (int i = 0; i < 16; ++i) {
              const int x = tx * kTile + i % kTile, y = ty * kTile + i / kTile;
              valid[i] = (x < width && y < height) ? -1 : 0;
              glm::vec3 o(0.0f), d(0.0f, 0.0f, -1.0f);
              if (valid[i]) makeRay(x, y, o, d);
              packet.ray.org_x[i] = o.x;
              packet.ray.org_y[i] = o.y;
              packet.ray.org_z[i] = o.z;
              packet.ray.dir_x[i] = d.x;
              packet.ray.dir_y[i] = d.y;
              packet.ray.dir_z[i] = d.z;
              packet.ray.tnear[i] = 0.0f;
              packet.ray.tfar[i] = std::numeric_limits<float>::infinity();
              packet.ray.time[i] = 0.0f;
              packet.ray.mask[i] = 0xffffffffu;
              packet.ray.id[i] = static_cast<unsigned>(i);
              packet.ray.flags[i] = 0;
              packet.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
              packet.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, scene, &context, &packet);
            for (int i = 0; i < 16; ++i) {
              if (!valid[i]) continue;
              const int x = tx * kTile + i % kTile, y = ty * kTile + i / kTile;
              onHit(x, y, RayHit{packet.hit.geomID[i], packet.hit.primID[i], packet.hit.u[i], packet.hit.v[i],
                                 packet.ray.tfar[i]});
            }
          }
      });
}

}  // namespace mrr
