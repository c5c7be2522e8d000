#pragma once
// A default light that lights the view (issue 34): for a scene without a light of its own, the
// direction, of a few fixed candidates, that lights the most of the surface the default view
// sees. Each candidate is tested with a small shadow map against a small G-buffer of the view,
// both rasterised here on the host (no oracle or GL needed: the choice belongs to the scene, so
// both paths render the same light).
#include <glm/glm.hpp>

#include <vector>

#include "common/camera.h"
#include "common/scene.h"

namespace mrr {

// The candidates, in the order they are tried (ties go to the earliest): the built-in default
// (DirectionalLight{}) first, then 8 azimuths (every 45°, from +z) at 30° and at 60° above the
// horizon. Directions the light travels (world, unit).
const std::vector<glm::vec3>& defaultLightCandidates();

// The share of the surface `camera` sees (pixels of a width × height G-buffer that hit
// geometry) that a directional light travelling along `direction` lights: the surface faces the
// light and nothing nearer the light covers it in a size × size shadow map fitted to the bounds.
// 0 when the view sees no surface. Deterministic, single-threaded float32.
struct LitShare {
  float share = 0.0f;   // lit pixels / surface pixels
  int surface = 0;      // surface pixels
};
LitShare litShare(const Scene& scene, const Camera& camera, const glm::vec3& direction, int width = 128,
                  int height = 72, int size = 256);

// The choice: each candidate's share on the view, the best (the earliest of equals).
struct DefaultLightChoice {
  glm::vec3 direction{0.0f};        // the chosen direction the light travels
  int chosen = 0;                   // its index in defaultLightCandidates()
  std::vector<float> shares;        // every candidate's lit share, in order
  int surface = 0;                  // the view's surface pixels
};
DefaultLightChoice chooseDefaultLight(const Scene& scene, const Camera& camera, float aspect);

}  // namespace mrr
