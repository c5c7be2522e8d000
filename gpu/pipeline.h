#pragma once
// The port end to end, mirroring cpu_ref/pipeline.cpp stage by stage, with every stage read
// back into the same FrameResult the oracle fills — so --stages, --report and probe work for
// --path gpu exactly as for --path cpu. Timings are glFinish + wall clock per stage (timer
// queries are wrong on llvmpipe, PLATFORM.md), readback included.
#include <memory>

#include "cpu_ref/pipeline.h"
#include "gpu/context.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

class GpuRenderer {
 public:
  explicit GpuRenderer(const Scene& scene, int deviceIndex = -1);
  // SSAO, SSM and SSGI, in multires and full mode.
  FrameResult render(const Camera& camera, const Constants& constants, const RenderOptions& options = {}) const;
  const std::string& renderer() const { return context_.renderer(); }

 private:
  const Scene& scene_;
  GlContext context_;
  GpuScene gpuScene_;
};

}  // namespace mrr::gpu
