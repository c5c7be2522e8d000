#pragma once
// Pinhole camera and the image geometry of SPEC §0: W×H pixels, padded up to a multiple of
// 2^(L-1) by extending the frustum right and down (same pixel size, same principal point).
#include <glm/glm.hpp>

namespace mrr {

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float yfov = 0.9f;  // vertical field of view of the W×H image, radians, (0, π)
};

// A camera at `eye` looking at `target`, Y up, with a vertical field of view in degrees.
Camera lookAt(const glm::vec3& eye, const glm::vec3& target, float fovDegrees);

// Everything a stage needs to turn full-res pixels into rays and view points into pixels.
// View space: x right, y up, looking down −z; linear depth z = −p.z > 0.
struct View {
  int width = 0, height = 0;              // W×H
  int paddedWidth = 0, paddedHeight = 0;  // multiples of the coarsest scale
  float focal = 1.0f;                     // pixels per unit of tan(angle)
  float cx = 0.0f, cy = 0.0f;             // principal point in full-res pixels = (W/2, H/2)
  glm::vec3 eye{0.0f};
  glm::vec3 right{1, 0, 0}, up{0, 1, 0}, forward{0, 0, -1};  // world-space camera basis

  // World → view space.
  glm::vec3 toView(const glm::vec3& world) const { return directionToView(world - eye); }
  glm::vec3 directionToView(const glm::vec3& d) const {
    return {glm::dot(d, right), glm::dot(d, up), -glm::dot(d, forward)};
  }
  // View → world space.
  glm::vec3 toWorld(const glm::vec3& v) const { return eye + directionToWorld(v); }
  glm::vec3 directionToWorld(const glm::vec3& v) const { return right * v.x + up * v.y - forward * v.z; }
  // View-space direction (not normalised) through the full-res continuous point (px, py).
  glm::vec3 viewRay(float px, float py) const { return {(px - cx) / focal, -(py - cy) / focal, -1.0f}; }
  // World-space direction (not normalised) through (px, py); its forward component is 1,
  // so the hit distance along it is the linear view depth.
  glm::vec3 worldRay(float px, float py) const {
    const glm::vec3 d = viewRay(px, py);
    return right * d.x + up * d.y + forward;
  }
  // Full-res continuous pixel coordinates of a view-space point in front of the camera.
  glm::vec2 project(const glm::vec3& p) const {
    const float z = -p.z;
    return {cx + focal * p.x / z, cy - focal * p.y / z};
  }
};

View makeView(const Camera& camera, int width, int height, int paddedWidth, int paddedHeight);

}  // namespace mrr
