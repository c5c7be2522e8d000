#include "scenes/cameras.h"

#include <glm/gtc/constants.hpp>

#include <cmath>

#include "common/error.h"

namespace mrr {

namespace {
constexpr float kDegree = glm::pi<float>() / 180.0f;

// `v` turned by `angle` radians about the unit axis `k` (Rodrigues).
glm::vec3 rotate(const glm::vec3& v, const glm::vec3& k, float angle) {
  const float c = std::cos(angle), s = std::sin(angle);
  return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1.0f - c);
}

// The camera turned in place by `pan` about its up axis and `tilt` about its right axis,
// then moved a fraction `dolly` of the way towards its target, along the new view.
Camera moved(const Camera& base, float pan, float tilt, float dolly) {
  const glm::vec3 view = base.target - base.eye;
  const glm::vec3 up = glm::normalize(base.up);
  glm::vec3 right = glm::cross(view, up);
  if (glm::dot(right, right) < 1e-12f) right = glm::vec3(1, 0, 0);
  right = glm::normalize(right);
  const glm::vec3 turned = rotate(rotate(view, up, pan), right, tilt);
  Camera c = base;
  c.eye = base.eye + dolly * turned;
  c.target = c.eye + (1.0f - dolly) * turned;
  return c;
}
}  // namespace

std::vector<Camera> benchCameras(const Camera& base, int count) {
  require(count >= 1 && count <= 64, "--cameras " + std::to_string(count) + ": must be in [1, 64]");
  // (pan, tilt, dolly): the base first, then turns and moves that each show other content.
  static const float kViews[8][3] = {{0, 0, 0},     {-16, 0, 0},   {16, 0, 0},      {0, -8, 0},
                                     {0, 8, 0.1f},  {-8, -4, 0.25f}, {8, 4, 0.25f}, {0, 0, 0.2f}};
  std::vector<Camera> cameras;
  for (int i = 0; i < count; ++i) {
    const float* v = kViews[i % 8];
    const float ring = static_cast<float>(i / 8);  // beyond 8: the same pattern, turned further
    cameras.push_back(moved(base, (v[0] + 4.0f * ring) * kDegree, v[1] * kDegree, v[2]));
  }
  return cameras;
}

const std::vector<std::string>& cameraPathKinds() {
  static const std::vector<std::string> kinds = {"orbit", "dolly"};
  return kinds;
}

std::vector<Camera> cameraPath(const Camera& base, const std::string& kind, int frames) {
  require(frames >= 2 && frames <= 10000, "--frames " + std::to_string(frames) + ": must be in [2, 10000]");
  std::vector<Camera> path;
  for (int t = 0; t < frames; ++t) {
    // s runs 0 → 1 → 0 with zero velocity at the ends (cosine ease): a smooth move, no jump.
    const float phase = static_cast<float>(t) / static_cast<float>(frames - 1);
    const float s = 0.5f - 0.5f * std::cos(2.0f * glm::pi<float>() * phase);
    if (kind == "orbit") {
      Camera c = base;
      const glm::vec3 up = glm::normalize(base.up);
      // a full period of a sine: 0 → +12° → 0 → −12° → 0, smooth and closed
      c.eye = base.target + rotate(base.eye - base.target, up, 12.0f * kDegree * std::sin(2.0f * glm::pi<float>() * phase));
      path.push_back(c);
    } else if (kind == "dolly") {
      path.push_back(moved(base, 0.0f, 0.0f, 0.3f * s));
    } else {
      throw MrrError("camera path " + kind + ": unknown (expected orbit or dolly)");
    }
  }
  return path;
}

}  // namespace mrr
