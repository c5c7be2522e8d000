#pragma once
// The path, chosen in one place: `--path cpu` is the oracle, `--path gpu` the port.
// render, probe, compare, bench and explore all make their renderers here and use them through
// common/renderer.h's interface.
#include <memory>
#include <string>

#include "common/renderer.h"
#include "common/scene.h"
#include "compare/bench/bench.h"

namespace mrr {

// "cpu" or "gpu"; anything else is MrrError naming --path. `scene` must outlive the renderer.
std::unique_ptr<FrameRenderer> makeRenderer(const std::string& path, const Scene& scene, const PathOptions& options = {});

// The bench's view of a path: its name, the device in words (threads and CPU for the oracle, the
// GL renderer and how stages are timed for the port) and a way to open a renderer per scene. The
// port's context is probed here, so a missing EGL device is one line before any work.
BenchPath benchPath(const std::string& path, int threads, const PathOptions& options = {});

// SPEC §14: the history a frame with the temporal term reads, when its previous camera is known
// (--prev-frame's, or --pan's: this camera moved by −pan along its right axis): that frame
// rendered first with the same settings and radii (`framedSize`), itself without a history or
// motion term, and what it leaves. Empty when the term is off or no previous camera is given.
FrameHistory previousFrameHistory(const FrameRenderer& renderer, const Camera& camera, const Settings& settings,
                                  float framedSize, const CostModel* costs, const ProgressFn& progress = {});

}  // namespace mrr
