#pragma once
// The directional light's shadow map (SPEC §6 SSM): orthographic, fitted to the scene's
// bounds, one Embree ray per texel centre cast from the light plane. Used by the shadow
// edges (SPEC §2), by SSM's PCSS, and by SSGI's one-tap sender shadow.
#include <glm/glm.hpp>

#include "common/camera.h"
#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/gbuffer.h"

namespace mrr {

ShadowMap renderShadowMap(const RayScene& rays, const DirectionalLight& light, const Bounds& bounds, int size);

// A receiver in light space (SPEC §6 SSM, docs/spec.md §6.4): its world position pushed along
// its normal by the bias, its biased depth, and the depth slope of its tangent plane, so that a
// tap at another texel is compared with the plane's depth there (receiver-plane depth bias).
// Shared by the one-tap test and PCSS so both agree.
struct Receiver {
  float u = 0.0f, v = 0.0f;            // texel coordinates
  float depth = 0.0f;                  // distance from the light plane, minus the depth bias
  float slopeU = 0.0f, slopeV = 0.0f;  // the tangent plane's depth change per texel in u and v
  bool facesLight = false;             // n·l > 0: the visible side faces the light
};
Receiver receiverAt(const ShadowMap& map, const glm::vec3& worldPosition, const glm::vec3& worldNormal,
                    float biasTexels);

// The receiver's depth at a tap (du, dv) texels away, on its tangent plane.
inline float receiverDepthAt(const Receiver& r, float du, float dv) {
  return r.depth + du * r.slopeU + dv * r.slopeV;
}

// One shadow-map test: 1 = lit, 0 = in shadow. A surface whose visible side faces away from the
// light is in its own shadow, whatever the map holds.
inline float shadowTest(const ShadowMap& map, const Receiver& r) {
  return r.facesLight && r.depth <= map.depthAt(r.u, r.v) ? 1.0f : 0.0f;
}

// The one-tap test at every pixel of a G-buffer (background: 1), for shadow edges and shading.
ImageU8 shadowTestImage(const GBuffer& g, const ShadowMap& map, const View& view, float biasTexels);

}  // namespace mrr
