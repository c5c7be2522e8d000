#pragma once
// The directional light's shadow map (SPEC §6 SSM): orthographic, fitted to the scene's
// bounds, one Embree ray per texel centre cast from the light plane. Used by the shadow
// edges (SPEC §2), by SSM's PCSS, and by SSGI's one-tap sender shadow.
#include <glm/glm.hpp>

#include "common/camera.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/gbuffer.h"

namespace mrr {

struct ShadowMap {
  int size = 0;
  float texel = 0.0f;              // world units per texel
  float farDepth = 0.0f;           // distance from the light plane to the bounds' farthest corner
  glm::vec3 origin{0.0f};          // corner of texel (0, 0) on the light plane
  glm::vec3 right{1, 0, 0}, up{0, 0, 1}, forward{0, -1, 0};  // forward = the light's direction
  ImageF depth;                    // distance from the light plane to the first hit; kNoBlocker on a miss

  static constexpr float kNoBlocker = 3.0e38f;

  // Continuous texel coordinates (u, v) and the distance from the light plane, of a world point.
  glm::vec3 lightCoordinates(const glm::vec3& world) const {
    const glm::vec3 d = world - origin;
    return {glm::dot(d, right) / texel, glm::dot(d, up) / texel, glm::dot(d, forward)};
  }
  // The stored depth at the texel holding (u, v); outside the map nothing blocks.
  float depthAt(float u, float v) const {
    if (!(u >= 0.0f && v >= 0.0f && u < static_cast<float>(size) && v < static_cast<float>(size))) return kNoBlocker;
    return depth.at(static_cast<int>(u), static_cast<int>(v));
  }
};

// The light's frame fitted to the bounds (steps 1–2 of renderShadowMap): basis, origin, texel
// size and depth range, with `depth` left empty. Shared by the oracle and the GL port
// (gpu/shadowmap.cpp), so both render the same map texel for texel.
ShadowMap shadowMapFrame(const DirectionalLight& light, const Bounds& bounds, int size);

ShadowMap renderShadowMap(const RayScene& rays, const DirectionalLight& light, const Bounds& bounds, int size);

// A receiver in light space: its world position pushed along its normal by the bias, and
// its biased depth (SPEC §6 SSM). Shared by the one-tap test and PCSS so both agree.
struct Receiver {
  float u = 0.0f, v = 0.0f;  // texel coordinates
  float depth = 0.0f;        // distance from the light plane, minus the depth bias
};
Receiver receiverAt(const ShadowMap& map, const glm::vec3& worldPosition, const glm::vec3& worldNormal,
                    float biasTexels);

// One shadow-map test: 1 = lit, 0 = in shadow.
inline float shadowTest(const ShadowMap& map, const Receiver& r) { return r.depth <= map.depthAt(r.u, r.v) ? 1.0f : 0.0f; }

// The one-tap test at every pixel of a G-buffer (background: 1), for shadow edges and shading.
ImageU8 shadowTestImage(const GBuffer& g, const ShadowMap& map, const View& view, float biasTexels);

}  // namespace mrr
