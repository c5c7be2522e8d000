#include "common/camera.h"

#include <glm/trigonometric.hpp>

#include <cmath>

#include "common/error.h"

namespace mrr {

Camera lookAt(const glm::vec3& eye, const glm::vec3& target, float fovDegrees) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.yfov = glm::radians(fovDegrees);
  return c;
}

View makeView(const Camera& camera, int width, int height, int paddedWidth, int paddedHeight) {
  View v;
  v.width = width;
  v.height = height;
  v.paddedWidth = paddedWidth;
  v.paddedHeight = paddedHeight;
  // SPEC §0: the field of view belongs to the W×H image; padding extends the frustum
  // right and down with the same pixel size and principal point.
  v.focal = 0.5f * static_cast<float>(height) / std::tan(0.5f * camera.yfov);
  v.cx = 0.5f * static_cast<float>(width);
  v.cy = 0.5f * static_cast<float>(height);
  v.eye = camera.eye;
  glm::vec3 fwd = camera.target - camera.eye;
  require(glm::length(fwd) > 0.0f, "camera: eye and target coincide");
  v.forward = glm::normalize(fwd);
  glm::vec3 r = glm::cross(v.forward, camera.up);
  if (glm::length(r) < 1e-6f) r = glm::cross(v.forward, glm::vec3(0, 0, 1));  // up ∥ forward
  v.right = glm::normalize(r);
  v.up = glm::cross(v.right, v.forward);
  return v;
}

}  // namespace mrr
