#include "frontend/renderers.h"

#include "common/error.h"
#include "common/frame_params.h"
#include "cpu_ref/pipeline.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"

namespace mrr {

std::unique_ptr<FrameRenderer> makeRenderer(const std::string& path, const Scene& scene, const PathOptions& options) {
  if (path == "cpu") return std::make_unique<Renderer>(scene);
  if (path == "gpu") return std::make_unique<gpu::GpuRenderer>(scene, options.glDevice, gpu::parseGpuTiming(options.gpuTiming));
  throw MrrError(optionName(Param::Path) + " " + path + ": unknown path (expected cpu or gpu)");
}

BenchPath benchPath(const std::string& path, int threads, const PathOptions& options) {
  std::string device;
  if (path == "cpu") {
    device = "cpu_ref (oracle), " + std::to_string(threads) + " threads on " + cpuModelName();
  } else if (path == "gpu") {
    const gpu::GpuTiming timing = gpu::parseGpuTiming(options.gpuTiming);
    const std::string renderer = gpu::GlContext(options.glDevice).renderer();
    device = "OpenGL 3.3 port on " + renderer + " (GPU-resident frame; " +
             (gpu::usesTimerQueries(timing, renderer) ? "GL_TIME_ELAPSED per stage" : "glFinish + wall clock per stage") + ")";
  } else {
    throw MrrError("--paths " + path + ": unknown path (expected cpu or gpu)");
  }
  return {path, device, [path, options](const Scene& scene) -> RenderFn {
            std::shared_ptr<const FrameRenderer> r = makeRenderer(path, scene, options);
            return [r](const Camera& c, const Constants& k, const RenderOptions& o) { return r->render(c, k, o); };
          }};
}

}  // namespace mrr
