#pragma once
// What a render writes: the --report JSON, the --stages multi-part EXR, and error figures
// against the full-res reference. Shared by `mrr render`, `mrr bench` and the tests.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>
#include <optional>
#include <string>
#include <vector>

#include "common/image_io.h"
#include "compare/metrics/metrics.h"
#include "compare/metrics/flip.h"
#include "common/frame.h"

namespace mrr {

struct RunInfo {
  std::string scene;
  std::string credit;
  std::string path = "cpu";
  int threads = 0;
  std::string renderer;      // gpu: GL_RENDERER
  std::string timingMethod;  // gpu: GpuRenderer::timingMethod
  int64_t memoryEstimateBytes = 0;  // the up-front estimate (common/memory.h)
  int64_t peakResidentBytes = 0;    // measured when the report is written
};

// SPEC §10 figures of `frame` against `reference` (a Mode::Full frame, same samples), on the
// effect buffer and on the shaded image, and their LDR-FLIP (compare/metrics/flip.h, default viewing
// conditions) as a viewer sees them: the effect buffer as grey, as `--out x.png` shows it,
// the shaded image sRGB-encoded, as `--shaded x.png`.
struct FrameErrors {
  ErrorFigures effect;
  ErrorFigures shaded;
  FlipStats effectFlip;
  FlipStats shadedFlip;
  // SPEC §13, with a gaze: the effect's RMS against full in each eccentricity ring (kRingDegrees).
  std::vector<double> ringRms;
};
// The eccentricity rings the report and the bench give figures in: [0, 5), [5, 10), ... degrees,
// the last open.
inline constexpr double kRingDegrees = 5.0;
inline constexpr int kRingCount = 6;
inline int eccentricityRing(float degrees) { return std::min(kRingCount - 1, static_cast<int>(degrees / kRingDegrees)); }
FrameErrors errorVsFull(const FrameResult& frame, const FrameResult& reference);
// SPEC §13's rings as the report and the bench count them: per ring, the level pixels shaded
// (every enabled level's stencil) whose sample pixel (levelSamplePixel) lies inside W×H, each in
// the ring `ringOf(px, py)` in [0, rings) gives its sample pixel.
std::vector<int64_t> shadedLevelPixelsByRing(const FrameResult& f, int rings, const std::function<int(int, int)>& ringOf);
// {"mean", "median", "q1", "q3", "max"}: how every report writes FLIP's figures.

nlohmann::json makeReport(const FrameResult& frame, const RunInfo& info, const std::optional<FrameErrors>& errors);

// Every stage as EXR parts with documented names (README "Output files").
std::vector<ExrPart> stageParts(const FrameResult& frame);

// Final effect buffer: float EXR or PNG preview by extension.
void writeFinal(const std::string& path, const FrameResult& frame);
// Shaded image: float EXR (linear) or sRGB PNG preview by extension.
void writeShaded(const std::string& path, const FrameResult& frame);

}  // namespace mrr
