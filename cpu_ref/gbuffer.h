#pragma once
// Stage 1 — G-buffer (SPEC §1): primary visibility at each enabled level's pixel centres.
#include <embree3/rtcore.h>

#include <memory>

#include "common/camera.h"
#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"

namespace mrr {

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
