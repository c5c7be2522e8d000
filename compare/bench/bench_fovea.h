#pragma once
// `mrr bench`'s foveation group (SPEC §13): what the level limit buys and costs.
//  - Rings: for a fixed gaze (the image centre) and each --fovea-ppd, every method with the gaze
//    only measuring (`--foveate off`: the method's own decisions) and with it foveating ("+gaze"),
//    beside `full`: per eccentricity ring the share of level pixels shaded, the effect's RMS and
//    mean FLIP against full, and the frame's time (median of the repeats).
//  - Motion: along the camera paths (orbit, dolly, as the flicker group uses), each frame with the
//    path's previous frame as --prev-frame ("+motion") and without: the frame's mean screen speed
//    |v| (SPEC §13 step 3) against the shaded share, with the time beside.
// Kept apart from compare/bench/bench.cpp's groups; runBench calls runFoveaGroup and the writers.
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compare/bench/bench.h"

namespace mrr {

// The rings' edges in degrees of eccentricity; the last ring is open (> 30°).
const std::vector<double>& foveaRingEdges();
// The ring of a full-res pixel at `dx`, `dy` pixels from the gaze, at `ppd`: e = √(dx² + dy²) / ppd
// (double), the ring i with edges[i] ≤ e < edges[i + 1].
int foveaRing(int dx, int dy, double ppd);

// One method, one ring, one scene and ppd.
struct FoveaRingRecord {
  std::string path, scene, effect, method;  // method: full, mrr, mrr+gaze, mrr-effect, mrr-effect+gaze, tiles, tiles+gaze
  int samples = 0, width = 0, height = 0, gazeX = 0, gazeY = 0;
  double ppd = 0.0;
  double fromDegrees = 0.0, toDegrees = -1.0;  // -1: open
  long long pixels = 0;              // full-res pixels of W×H in the ring
  long long shadedLevelPixels = 0;   // level pixels shaded whose sample pixel (levelSamplePixel) is in the ring
  double shadedShare = 0.0;          // shadedLevelPixels / pixels
  double rms = 0.0;                  // the effect buffer against full's, over the ring's pixels and channels
  double flip = 0.0;                 // mean LDR-FLIP (at this ppd) of the effect buffer against full's, over the ring
  double frameShare = 0.0;           // the whole frame's shaded level pixels / W·H
  double effectMs = 0.0;             // the frame's time less its full-res G-buffer, median of the repeats
  bool fellBack = false;             // the never-slower rule shaded the frame at full res
  bool budgeted = false;             // SPEC §12.4: its a-posteriori term spent a budget in predicted time
};

// One method on one frame of a camera path.
struct FoveaMotionRecord {
  std::string path, scene, effect, kind, method;  // kind: orbit, dolly; method: mrr, mrr+motion, mrr-effect, ...
  int samples = 0, width = 0, height = 0, frame = 0, frames = 0;
  double meanSpeed = 0.0;    // mean |v| over the W×H pixels on geometry, full-res pixels per frame (the +motion run's)
  double shadedShare = 0.0;  // shaded level pixels / W·H
  double effectMs = 0.0;     // median of the repeats
  bool fellBack = false;
};

struct FoveaResults {
  std::vector<FoveaRingRecord> rings;
  std::vector<FoveaMotionRecord> motion;
};

// Runs the group on one path (progress on stderr); appends to `out`.
void runFoveaGroup(const BenchOptions& options, const BenchPath& path, FoveaResults& out);
// Steps the group adds to the progress count.
size_t foveaSteps(const BenchOptions& options);

// Markdown tables (empty string when nothing ran), JSON ({"rings": [...], "motion": [...]}) and
// CSV (written beside --csv F as F's stem + "-fovea.csv" and "-fovea-motion.csv").
std::string foveaMarkdown(const FoveaResults& results);
nlohmann::json foveaJson(const FoveaResults& results);
std::string foveaRingsCsv(const FoveaResults& results);
std::string foveaMotionCsv(const FoveaResults& results);
std::string foveaCsvPath(const std::string& csvPath, const std::string& suffix);
// Sanity: every share in [0, 1], every error finite; full's error 0; a "+gaze" method shades at
// most its own method's level pixels in every ring (SPEC §13 clears masks only). One line each.
std::vector<std::string> foveaSanityChecks(const FoveaResults& results);

}  // namespace mrr
