#pragma once
// Stage 1 — G-buffer (SPEC §1): primary visibility at each enabled level's pixel centres.
#include <embree3/rtcore.h>

#include <memory>

#include "common/camera.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"

namespace mrr {

struct GBuffer {
  GBuffer() = default;
  GBuffer(int w, int h)  // all background
      : width(w), height(h), depth(w, h, 1), position(w, h, 3), normal(w, h, 3), albedo(w, h, 3), hit(w, h, 1) {}
  // Unfilled: for a renderer that writes every pixel, background included.
  static GBuffer uninitialised(int w, int h) {
    GBuffer g;
    g.width = w;
    g.height = h;
    g.depth = ImageF::uninitialised(w, h, 1);
    g.position = ImageF::uninitialised(w, h, 3);
    g.normal = ImageF::uninitialised(w, h, 3);
    g.albedo = ImageF::uninitialised(w, h, 3);
    g.hit = ImageU8::uninitialised(w, h, 1);
    return g;
  }

  int width = 0, height = 0;
  ImageF depth;     // linear view depth z > 0 (0 on background)
  ImageF position;  // view-space position, 3 channels
  ImageF normal;    // view-space shading normal, unit, facing the camera, 3 channels
  ImageF albedo;    // base colour, 3 channels
  ImageU8 hit;      // 1 = geometry, 0 = background

  glm::vec3 positionAt(int x, int y) const {
    return {position.at(x, y, 0), position.at(x, y, 1), position.at(x, y, 2)};
  }
  glm::vec3 normalAt(int x, int y) const {
    return {normal.at(x, y, 0), normal.at(x, y, 1), normal.at(x, y, 2)};
  }
};

// The scene in an Embree BVH, built once and shared by every level and frame.
class RayScene {
 public:
  explicit RayScene(const Scene& scene);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  const Scene& scene() const { return scene_; }
  RTCScene handle() const { return rtcScene_; }

 private:
  const Scene& scene_;
  RTCDevice device_ = nullptr;
  RTCScene rtcScene_ = nullptr;
};

// Casts one ray per pixel centre of `level` ((x+0.5)·s, (y+0.5)·s in full-res pixels),
// in 4×4 packets (rtcIntersect16), in parallel over tiles.
GBuffer renderGBuffer(const RayScene& rays, const View& view, const LevelConstants& level);

}  // namespace mrr
