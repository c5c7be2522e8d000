#pragma once
// The oracle, end to end: scene → G-buffers → edges → masks → sub-images → blend.
// Data flows one way through these stages; FrameResult (common/frame.h) keeps every
// intermediate so that --stages, --report and probe can show them.
#include <array>
#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "common/camera.h"
#include "common/cost_model.h"
#include "common/frame.h"
#include "common/params.h"
#include "common/renderer.h"
#include "common/scene.h"
#include "cpu_ref/blend.h"
#include "cpu_ref/edges.h"
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/masks.h"
#include "cpu_ref/shadowmap.h"
#include "cpu_ref/ssao.h"

namespace mrr {

class Renderer final : public FrameRenderer {
 public:
  explicit Renderer(const Scene& scene);  // builds the BVH
  FrameResult render(const Camera& camera, const Constants& constants, const RenderOptions& options = {}) const override;
  const char* path() const override { return "cpu"; }
  std::string device() const override { return "cpu_ref (oracle)"; }
  std::string timingMethod() const override { return ""; }
  const Scene& scene() const { return scene_; }
  double bvhBuildMs() const { return bvhBuildMs_; }

 private:
  const Scene& scene_;
  double bvhBuildMs_ = 0.0;
  std::chrono::steady_clock::time_point buildStart_ = std::chrono::steady_clock::now();
  RayScene rays_;  // built after buildStart_ is taken (member order), timed in the constructor
  // Scratch reused across frames, so a steady stream of frames does not page-fault it in
  // again each time (render() is therefore not re-entrant).
  mutable std::array<OccluderPlanes, kLevelCount> planes_;
};

}  // namespace mrr
