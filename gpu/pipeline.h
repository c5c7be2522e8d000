#pragma once
// The port end to end, mirroring cpu_ref/pipeline.cpp stage by stage, with every stage read
// back into the same FrameResult the oracle fills with keepStages — so --stages, --report and
// probe work for --path gpu exactly as for --path cpu. Without keepStages (the benchmark, a
// plain render) the frame stays on the GPU: nothing comes back inside the timed frame but the
// never-slower rule's few integers, and after it what the caller asked for
// (RenderOptions::outputs; docs/port.md, "The GPU-resident frame"). Timings are glFinish + wall
// clock per stage on llvmpipe (its timer queries are wrong, docs/platform.md), timer queries
// elsewhere; with keepStages each stage's readbacks are inside its timing.
#include <memory>
#include <string>

#include "common/frame.h"
#include "common/renderer.h"
#include "gpu/context.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// Whether a timing name is of a stage only the port has, beside the oracle's (TimedOn::Port in
// common/stages.h's kTimed): `stencils` (host-made stencils of full, uniform-k, tiles or a
// never-slower fallback, uploaded for the stencil test).
bool isPortOnlyStage(const std::string& stage);

// How stages are timed. wall: glFinish + a steady clock around each stage (what llvmpipe needs:
// its GL_TIME_ELAPSED figures are wrong, docs/platform.md). query: GL_TIME_ELAPSED around each
// stage's GL work, read when the frame is done, and no glFinish between stages; `total` stays
// on the wall clock. auto: wall on Mesa's
// software rasterisers (llvmpipe, softpipe), query elsewhere (NVIDIA). passes: wall, and every
// draw timed alone too (gpu/pass_clock.h, a diagnostic: FrameResult::passTimings).
enum class GpuTiming { Auto, Wall, Query, Passes };
GpuTiming parseGpuTiming(const std::string& name);  // auto | wall | query | passes; throws MrrError
// Whether `timing` means timer queries on the GL renderer named `renderer` (GL_RENDERER).
bool usesTimerQueries(GpuTiming timing, const std::string& renderer);

class GpuRenderer final : public FrameRenderer {
 public:
  explicit GpuRenderer(const Scene& scene, int deviceIndex = -1, GpuTiming timing = GpuTiming::Auto);
  // SSAO, SSM and SSGI, in multires and full mode.
  FrameResult render(const Camera& camera, const Constants& constants, const RenderOptions& options = {}) const override;
  const char* path() const override { return "gpu"; }
  std::string device() const override { return context_.renderer(); }
  const std::string& renderer() const { return context_.renderer(); }
  bool timerQueries() const { return timerQueries_; }
  std::string timingMethod() const override;  // for the report's timing_method

 private:
  const Scene& scene_;
  GlContext context_;
  GpuScene gpuScene_;
  bool timerQueries_ = false;
  bool passTiming_ = false;
};

}  // namespace mrr::gpu
