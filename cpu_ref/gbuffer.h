#pragma once
// Stage 1 — G-buffer (SPEC §1): primary visibility at the full-res pixel centres, and each
// coarser level's G-buffer subsampled from it.
#include <embree3/rtcore.h>

#include <memory>
#include <vector>

#include "common/camera.h"
#include "common/frame.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"

namespace mrr {

struct CutoutHits;

// The scene in an Embree BVH, built once and shared by every level and frame. A mesh with an
// alpha cutout gets an Embree filter function that refuses hits on its transparent texels
// (docs/spec.md §1.1), so every ray (G-buffer and shadow map alike) passes through them.
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
  std::vector<std::unique_ptr<CutoutHits>> cutoutHits_;  // the filter functions' user data
};

// The texture coordinate at barycentrics (u, v) of triangle `primitive` of a mesh with
// texcoords, interpolated as the G-buffer interpolates positions (docs/spec.md §1.1).
glm::vec2 texcoordAt(const Mesh& mesh, unsigned primitive, float u, float v);

// Whether a hit at barycentrics (u, v) of triangle `primitive` is on an opaque texel: always
// for a mesh without a cutout (docs/spec.md §1.1).
bool opaqueHit(const Scene& scene, const Mesh& mesh, unsigned primitive, float u, float v);

// Casts one ray per pixel centre of `level` ((x+0.5)·s, (y+0.5)·s in full-res pixels),
// in 4×4 packets (rtcIntersect16), in parallel over tiles. The pipeline casts level 0 alone.
GBuffer renderGBuffer(const RayScene& rays, const View& view, const LevelConstants& level);

// Level ℓ's G-buffer from level 0's (SPEC §1): pixel (x, y) is a copy of full-res pixel
// (levelSamplePixel(x, s), levelSamplePixel(y, s)), every channel bit for bit. No ray, no
// triangle: the coarse levels see exactly the surfaces the full-res image does.
GBuffer subsampleGBuffer(const GBuffer& full, const LevelConstants& level);

}  // namespace mrr
