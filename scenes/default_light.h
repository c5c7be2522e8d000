#pragma once
// A default light that lights the view: for a scene without a light of its own, the
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

// What the view frames (docs/spec.md §6, the automatic radii): the height of the view at the
// median depth of the surface it sees, 2 z̃ tan(fov_y / 2), z̃ the median (the lower middle) of
// the depths along the view direction of the covered pixels of the same 72-high G-buffer (BLEND
// surfaces left out, as the framing leaves them). makeConstants scales it into the automatic
// SSAO and SSGI radii. Resolved here on the host, single-threaded float32: both paths read the
// radii it gives. A view that sees no surface gets the scene's diagonal.
struct FramedSize {
  float size = 0.0f;         // the framed size, world units
  float medianDepth = 0.0f;  // z̃; 0 when the view sees no surface
  int surface = 0;           // covered probe pixels
  float diagonal = 0.0f;     // the scene's bounding diagonal (the basis before the view-framed default)
};
FramedSize framedSize(const Scene& scene, const Camera& camera, float aspect);

}  // namespace mrr
