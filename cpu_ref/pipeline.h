#pragma once
// The oracle, end to end: scene → G-buffers → edges → masks → sub-images → blend, the stages of
// cpu_ref/oracle.h in the order of common/driver.cpp (where the never-slower rule and the
// a-posteriori term feed back). FrameResult (common/frame.h) keeps every intermediate so that
// --stages, --report and probe can show them.
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
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/oracle.h"

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
  // The oracle's stages on this scene (cpu_ref/oracle.h), for a caller that runs one alone.
  const OracleStages& stages() const { return stages_; }

 private:
  const Scene& scene_;
  double bvhBuildMs_ = 0.0;
  std::chrono::steady_clock::time_point buildStart_ = std::chrono::steady_clock::now();
  RayScene rays_;  // built after buildStart_ is taken (member order), timed in the constructor
  // Its scratch is reused across frames (render() is therefore not re-entrant).
  OracleStages stages_;
};

}  // namespace mrr
