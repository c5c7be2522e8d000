#pragma once
// The never-slower rule (SPEC §11), fitted and checked:
//  - `mrr bench --calibrate FILE` fits the cost model's figures on the machine at hand, per
//    path, from frames that differ in what the model separates (share on geometry, sample
//    count, size): least squares over medians of repeats;
//  - `mrr bench --rule-sweep FILE` renders frames nobody tuned the model to (the shared scenes,
//    the built-ins and the stress scenes; the catalogue camera, the default framing, the sky
//    and a close-up; 320×180 to 1920×1080; low and high sample counts) in full and in mrr with
//    the rule off, and where the rule falls back also with it on, and counts how often the rule
//    chose the faster mode, and what it cost where it did not. scripts/rule-chart.py draws it.
#include <iosfwd>
#include <map>
#include <string>
#include <vector>

#include "common/camera.h"
#include "common/cost_model.h"
#include "common/stages.h"
#include "compare/bench/bench.h"

namespace mrr {

// The time a frame's stages (timing name → ms, as stageMs gives them) spend in stages of class
// `cost` (common/stages.h, kTimed): what the sweep's frame and rests and the calibration's fits
// sum. A name the stage list does not know throws MrrError: renamed, a stage would otherwise drop
// out of its sum and zero a term of the never-slower fits.
double costClassMs(const std::map<std::string, double>& ms, CostClass cost);

struct RuleView {
  std::string name;  // catalogue, default, sky, close-up
  Camera camera;
};
// The catalogue's camera; the default framing (frameScene); the sky: from the catalogue's eye,
// 50° above the horizon; a close-up: a quarter of the way from the target to the eye.
inline constexpr size_t kRuleViewCount = 4;
std::vector<RuleView> ruleViews(const Scene& scene, const Camera& catalogue, float aspect);

// Fits the model's costs on `path` (SPEC §11's calibration): builtin:corner (a few creases:
// sparse stencils), builtin:demo and builtin:bumpy (edges everywhere) at 320×180, 640×360 and
// 1280×720 from the catalogue camera, the sky and a close-up; every
// effect in mode full at two sample counts (a, b and c by least squares over H, H·N and
// W·H − H), and in mode mrr with the rule off (s, d, g, β, ε, μ, k).
CostModel calibrateCostModel(const BenchPath& path, int repeats, int threads);

// One frame of the method (rule off) the calibration measured: what it priced and what it took.
struct CalibrationFrame {
  Effect effect;
  Constants constants;
  FrameCounts counts;
  double restMs;  // the frame less what every mode pays alike (the full-res G-buffer, shade, …)
};
// s and k for effect e (SPEC §11): least squares over the frames' rests, the model's other
// figures fixed; s is kept in [1, 2] (a stencilled pixel costs no less than a dense one, and the
// first a stencil takes no more than twice the dense mean), k then refitted alone.
void fitSparseFactorAndFixedCost(CostModel& model, Effect e, const std::vector<CalibrationFrame>& frames);

// φ_ℓ and η_ℓ (SPEC §11's early estimate of the stencils, estimateStencilPixels): per level
// below the coarsest, the pair with the least relative squared error against the frames' |S_ℓ|.
// A level no frame shades keeps the model's.
void fitStencilFill(CostModel& model, const std::vector<CalibrationFrame>& frames);

struct RuleSweepOptions {
  std::vector<std::string> scenes = {"arcade",         "apartment",     "cornell",        "builtin:demo",
                                     "builtin:boxes",  "builtin:shadows", "builtin:fence", "builtin:bumpy",
                                     "builtin:wires",  "builtin:alledges", "builtin:plane"};
  int configsPerView = 2;  // frames per scene and view, cycling through sizes, effects and samples
  int repeats = 3;         // medians of this many, after one warm-up
  int threads = 0;
  std::string jsonOut;
  std::string machine;
  std::string costModelFile;  // empty: the built-in model of each path; "{path}" is replaced by its name
};

// `file` with its "{path}" (if any) replaced by the path's name: `--calibrate FILE` and
// `--cost-model FILE` name one file per path so.
std::string withPathName(std::string file, const std::string& path);
// The cost model the sweep and the replay decide with on `path`: `file` (`--cost-model`, as
// `--calibrate` wrote it, withPathName) or, empty, the built-in one.
CostModel ruleCostModel(const std::string& file, const std::string& path);

// One frame of the sweep: its effect, samples and size.
struct SweepConfig {
  Effect effect;
  int samples, width, height;
};
// The configuration of the `frame`-th frame (scenes × views × configsPerView, in that order) of
// `path`'s sweep of `framesPerPath` frames: a cycle through the sweep's sizes, effects and sample
// counts, the oracle's frames from its start and the port's on from where the oracle's end, so a
// path sweeps the same frames whether or not the run also sweeps the other path.
SweepConfig ruleSweepConfig(const std::string& path, size_t frame, size_t framesPerPath);

// Runs the sweep on every path, writes the JSON, prints the summary (Markdown); returns 0.
int runRuleSweep(const RuleSweepOptions& options, const std::vector<BenchPath>& paths, std::ostream& out);
// `mrr bench --rule-replay FILE`: re-decides every frame of a sweep's JSON with the cost model of
// its path (ruleCostModel: `costModelFile` or the built-in one), from the counts the sweep recorded, and judges it by the times the sweep
// measured: what this build's model decides on frames measured before, without rendering again
// (a decision is a function of the counts). Prints the summary and every frame decided or judged
// otherwise than recorded; with `jsonOut`, writes the sweep re-decided there (rule_ms null where
// only the replay falls back: that time was not measured). Throws MrrError on a file that is not a sweep.
int replayRuleSweep(const std::string& sweepFile, const std::string& costModelFile, const std::string& jsonOut,
                    std::ostream& out);

}  // namespace mrr
