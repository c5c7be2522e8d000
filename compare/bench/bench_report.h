#pragma once
// What `mrr bench` measured, and everything written from it: the sanity checks, the Markdown
// tables, JSON and CSV, and the HTML page with its charts (drawn by compare/report/report.py).
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compare/metrics/metrics.h"
#include "compare/bench/bench.h"
#include "compare/bench/bench_fovea.h"

namespace mrr {

// One method on one setting (medians over the repeats).
struct BenchRecord {
  std::string path, scene, group, method, effect;  // group: main, samples, resolution, stress
  int camera = 0, width = 0, height = 0, samples = 0;
  std::map<std::string, double> stageMs;  // median per stage, and "total"
  std::map<std::string, double> passMs;   // --gpu-timing passes: median per "stage program" (FrameResult::passTimings)
  double effectMs = 0.0;                  // total − the full-res G-buffer (shared by every method)
  double totalMs = 0.0;
  long long shadedPixels = 0;
  double idealSpeedup = 1.0;     // W·H / shaded pixels (SPEC §4, §9)
  double idealSpeedupHit = 1.0;  // the same over pixels that hit geometry (FrameResult::idealSpeedupHit)
  double measuredSpeedup = 1.0;  // full's effect time / this method's, same run
  double fullEffectMs = 0.0;     // full's effect time in the same run
  // Cold single frames (BenchOptions::coldRuns; 0: not measured): the median effect time of
  // fresh `mrr render` processes, and full's over this method's, the same way; and the median
  // wall time of such a process, start to exit (scene load, BVH or GL set-up, the one frame,
  // its report): what a user waits for one frame.
  double coldEffectMs = 0.0;
  double coldSpeedup = 0.0;
  double coldProcessMs = 0.0;
  bool fellBack = false;         // mrr: the never-slower rule shaded this frame at full res
  ErrorFigures error;            // SPEC §10, the effect buffer against full
  double shadedRms = 0.0;        // RMS of the shaded image against full's
  double flip = 0.0;             // mean LDR-FLIP of the effect buffer (as grey) against full's
  double shadedFlip = 0.0;       // mean LDR-FLIP of the shaded image against full's
  // BenchOptions::expectationSeeds: the effect buffer against full's mean over K other seeds
  // (SPEC §10); NaN where not measured (off, or an effect without noise)
  double expectationRms = std::nan(""), expectationMae = std::nan("");
};

// One method along one camera path.
struct StabilityRecord {
  std::string path, scene, effect;
  int samples = 0;
  std::string kind;  // orbit, dolly
  int frames = 0, width = 0, height = 0;
  std::string method;
  double flicker = 0.0;  // SPEC §10
  double meanRms = 0.0;
  double flipFlicker = 0.0;  // SPEC §10: mean |FLIP_t − FLIP_{t−1}| against full, per pixel
  double meanFlip = 0.0;     // the mean per-frame mean FLIP against full
  // BenchOptions::expectationSeeds: flicker and mean RMS against the expectation instead of
  // full (SPEC §10), full's own row included; NaN where not measured
  double expectationFlicker = std::nan(""), expectationMeanRms = std::nan("");
};

struct BenchResults {
  BenchOptions options;
  std::map<std::string, std::string> devices;  // path → what ran it
  std::vector<BenchRecord> records;
  std::vector<StabilityRecord> stability;
  int threads = 0;
  FoveaResults fovea;  // the foveation group (compare/bench/bench_fovea.h)
};

// The figures' sanity: full's error is 0 (its repeats give the same
// bits); it shades W·H pixels; no method is measured faster than its ideal speedup (beyond
// timing noise); every error is finite. One line per failure.
std::vector<std::string> sanityChecks(const BenchResults& results);

std::string benchMarkdown(const BenchResults& results, const std::vector<std::string>& failures);
nlohmann::json benchJson(const BenchResults& results, const std::vector<std::string>& failures);
std::string benchCsv(const BenchResults& results);
// The stability table as CSV (one row per path, scene, effect, camera path and method), written
// beside --csv F as stabilityCsvPath(F): F's folder, F's stem + "-stability.csv".
std::string benchStabilityCsv(const BenchResults& results);
std::string stabilityCsvPath(const std::string& csvPath);

// DIR/index.html with the charts (DIR/charts/*.svg and *.png, drawn by matplotlib), the tables
// and the example images (written by the sweep into DIR/images/). Needs requireReportPython().
void writeBenchReport(const std::string& dir, const BenchResults& results, const std::vector<std::string>& failures);

// The paper's plotted figures ($MRR_PAPER_FIGURES; docs/figures.md, "The paper's sweeps beside the
// paper's figures"): speedup as a factor (1 + pct/100) or RMS, by figure, effect, samples and
// size. Empty when the file is absent.
struct PaperFigure {
  std::string figure, effect;
  int samples = 0, width = 0, height = 0;
  double speedup = 0.0;  // 0 when the row gives an RMS
  double rms = 0.0;      // 0 when the row gives a speedup
};
std::vector<PaperFigure> readPaperFigures(const std::string& path);

}  // namespace mrr
