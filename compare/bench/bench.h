#pragma once
// `mrr bench`: speed against accuracy, measured (SPEC §§9–11). For every path ×
// scene × camera × size × effect × sample count it renders `full` and each method side by
// side in one process, alternating, and keeps per method the median time of several repeats
// (after a warm-up), per stage, the shaded pixels and ideal speedup, the measured speedup
// against `full`, and every error figure of SPEC §10 against `full` with the same samples.
// Then the paper's sweeps (speedup against samples and against resolution, RMS against
// resolution), temporal stability along camera paths (flicker), and the stress scenes.
// Results go to JSON, CSV and Markdown; `--report DIR` writes an HTML page with the charts
// (compare/bench/bench_report). Progress goes to stderr.
#include <functional>
#include <map>
#include <memory>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/cost_model.h"
#include "common/camera.h"
#include "common/frame.h"
#include "common/methods.h"
#include "common/scene.h"

namespace mrr {

// One renderer behind either path: the bench does not know which it drives.
using RenderFn = std::function<FrameResult(const Camera&, const Constants&, const RenderOptions&)>;
struct BenchPath {
  std::string name;    // "cpu" or "gpu"
  std::string device;  // "cpu_ref, N threads on <CPU>" or the GL renderer
  std::function<RenderFn(const Scene&)> open;  // builds the renderer (BVH, GL context) for a scene
};

struct BenchOptions {
  // The main sweep: chart 1 (speedup against RMS, one point per method × setting).
  std::vector<std::string> scenes = {"arcade", "apartment", "cornell", "builtin:demo"};
  std::vector<std::pair<int, int>> sizes = {{1280, 720}};
  std::vector<std::string> effects = {"ssao", "ssm", "ssgi"};
  std::vector<int> samples;  // empty: the paper's middle count per effect (64, 196, 288)
  std::vector<std::string> methods = benchDefaultMethods();  // the method table's (common/methods.h)
  int cameras = 8;           // views per scene (scenes/cameras.h), as in the paper
  int repeats = 3;           // median of this many timed runs, after one warm-up
  int threads = 0;           // the oracle's threads (0 = all cores)
  // The paper's sweeps, on the first scene's first camera: Fig. 6 (speedup against samples,
  // at sweepSize) and Figs. 7 and 9 (speedup and RMS against resolution).
  bool paperSweeps = true;
  std::pair<int, int> sweepSize = {1280, 720};
  std::vector<std::pair<int, int>> resolutions = {{1280, 720}, {1920, 1080}};
  std::vector<int> ssaoSweep = {16, 32, 64, 128, 256}, ssmSweep = {100, 144, 196, 256, 324}, ssgiSweep = {24, 80, 288};
  // Stability (SPEC §10): each camera path of `frames` frames, every method, flicker.
  int frames = 60;
  std::pair<int, int> stabilitySize = {320, 180};
  std::vector<std::string> stabilityScenes = {"builtin:demo", "arcade"};
  std::vector<std::string> stabilityEffects = {"ssao"};
  // The stress scenes, each with every method and mrr without the never-slower rule.
  std::vector<std::string> stressScenes = {"builtin:bumpy", "builtin:wires", "builtin:alledges", "builtin:plane"};
  std::pair<int, int> stressSize = {1280, 720};
  // The foveation group (SPEC §13; compare/bench/bench_fovea.h): per eccentricity ring for a
  // gaze at the image centre, at each ppd, and the shaded share against screen speed along the
  // camera paths (foveaFrames frames each; 0: none). Off unless asked (`mrr bench` asks unless
  // --no-fovea); foveaOnly asks for it and skips every other group.
  bool fovea = false, foveaOnly = false;
  std::vector<std::string> foveaScenes = {"arcade", "builtin:demo"};
  std::vector<std::string> foveaMethods = mrr::foveaMethods();
  std::pair<int, int> foveaSize = {1280, 720};        // the rings
  std::pair<int, int> foveaMotionSize = {640, 360};  // the camera paths
  std::vector<double> foveaPpds = {30.0, 3840.0 * 3.14159265358979323846 / 180.0};  // 30 and the default, 67.02
  std::string foveaEffect = "ssao";
  int foveaSamples = 0;  // 0: the paper's middle count (ssao 64, ssm 196, ssgi 288)
  int foveaFrames = 8;
  // Single frames as a user renders them: per main-sweep setting, this many fresh `mrr render`
  // processes each of full and of the methods of kColdMethods that `methods` holds,
  // alternating (0: none), their medians beside the warm ones.
  int coldRuns = 0;
  // The error against the effect's expectation (SPEC §10): for SSAO and SSGI, whose estimator
  // draws noise, full's mean over this many other seeds (1..K) is a second reference beside
  // full, on every main-sweep frame and every camera-path frame (0: off). SSM has no noise.
  // The paper's sweeps and the stress scenes go without it.
  int expectationSeeds = 0;
  // Outputs.
  std::string jsonOut, csvOut, markdownOut, reportDir;
  bool check = false;  // exit 1 when a sanity check fails (full's error 0, ideal ≥ measured, …)
  std::string machine;  // filled by runBench when empty: the CPU model and thread count
};


// Runs everything; writes the outputs; prints the Markdown tables to `out`. Returns the exit
// code (1 when --check found a failed sanity check).
int runBench(const BenchOptions& options, const std::vector<BenchPath>& paths, std::ostream& out);

// Shared with compare/rule/rule.cpp.
double median(std::vector<double> v);
// A method as the bench names it: a row of the method table and its switches
// ("mrr-effect+c4+p0.15", "mrr+norule": common/methods.h parseMethodSpec).
Settings settingsFor(const std::string& method, Effect effect, int w, int h, int samples);
// One scene opened on one path: the scene, its default camera and its renderer.
struct OpenScene {
  std::string name;
  std::unique_ptr<Scene> scene;
  Camera camera;
  RenderFn render;
};
OpenScene openScene(const std::string& name, const BenchPath& path);
std::map<std::string, double> stageMs(const FrameResult& f);  // a frame's timings by stage (summed)
// The method's own time (docs/spec.md §10) from a frame's timings by stage: the frame less the
// full-res G-buffer and the shaded image for viewing, which every method pays alike.
double effectMs(const std::map<std::string, double>& ms);

// The CPU's model name, from /proc/cpuinfo.
std::string cpuModelName();

}  // namespace mrr
