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

FrameHistory previousFrameHistory(const FrameRenderer& renderer, const Camera& camera, const Settings& settings,
                                  float framedSize, const CostModel* costs, const ProgressFn& progress) {
  const Constants c = makeConstants(settings, framedSize);
  if (!c.temporal.on() || !settings.foveation.motion) return {};
  Settings previous = settings;  // the previous frame: no previous one of its own
  previous.foveation.motion = previous.foveation.panned = false;
  previous.foveation.pan = 0.0f;
  Camera before = camera;
  if (settings.foveation.panned) {  // SPEC §13 step 3's previous view: the eye (and target) moved by −pan·right
    const View view = makeView(camera, c.width, c.height, c.paddedWidth, c.paddedHeight);
    before.eye = camera.eye - settings.foveation.pan * view.right;
    before.target = camera.target - settings.foveation.pan * view.right;
  } else {
    before.eye = settings.foveation.prevEye;
    before.target = settings.foveation.prevTarget;
    before.up = settings.foveation.prevUp;
    before.yfov = settings.foveation.prevYfov;
  }
  FrameResult f = renderer.render(before, makeConstants(previous, framedSize), {false, progress, costs});
  return std::move(f.history);
}

}  // namespace mrr
