#pragma once
// One interface for both paths: the oracle (cpu_ref/pipeline.h Renderer) and the port
// (gpu/pipeline.h GpuRenderer) render a frame into the same FrameResult. Who picks the path —
// the command line, compare, bench, explore — asks one factory, frontend/renderers.h
// makeRenderer, and works with this interface from then on.
#include <string>

#include "common/camera.h"
#include "common/frame.h"
#include "common/params.h"

namespace mrr {

// What choosing a path takes beside its name (the port's; the oracle needs none).
struct PathOptions {
  int glDevice = -1;               // --gl-device: the EGL device (-1: the first that gives GL 3.3 core)
  std::string gpuTiming = "auto";  // --gpu-timing: auto, wall, query or passes
};

class FrameRenderer {
 public:
  virtual ~FrameRenderer() = default;
  virtual FrameResult render(const Camera& camera, const Constants& constants,
                             const RenderOptions& options = {}) const = 0;
  virtual const char* path() const = 0;         // "cpu" or "gpu": the --path that chose it
  virtual std::string device() const = 0;       // what renders: "cpu_ref (oracle)" or the GL renderer
  virtual std::string timingMethod() const = 0;  // the report's timing_method ("" on the oracle)
};

}  // namespace mrr
