// `mrr bench`: speed against accuracy, every method against full side by side (compare/bench/bench.h);
// and the never-slower rule's calibration, sweep and replay (compare/rule/rule.h).
#include <cmath>
#include <iostream>
#include <thread>

#include "app/commands.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/methods.h"
#include "compare/report/report_python.h"
#include "compare/rule/rule.h"
#include "frontend/options.h"
#include "frontend/renderers.h"
#include "gpu/context.h"

namespace mrr {

namespace {

// The foveation group (SPEC §13; compare/bench/bench_fovea.h).
void addFoveaOptions(CLI::App& b, BenchCommand& c) {
  BenchOptions& o = c.options;
  b.add_flag("--no-fovea", c.noFovea, "skip the foveation group");
  b.add_flag("--fovea-only", o.foveaOnly, "run the foveation group alone (no main sweep, sweeps, paths or stress)");
  b.add_option("--fovea-scenes", o.foveaScenes, "scenes of the foveation group")->capture_default_str();
  b.add_option("--fovea-size", c.foveaSize, "size of the foveation group's rings (default 1280x720)");
  b.add_option("--fovea-motion-size", c.foveaMotionSize, "size of the foveation group's camera paths (default 640x360)");
  b.add_option("--fovea-ppd", o.foveaPpds,
               "pixels per degree of the rings, gaze at the image centre (default 30 and 67.02, the viewing default)");
  b.add_option("--fovea-methods", o.foveaMethods,
               "methods with and without the gaze and the previous frame: mrr, mrr-effect (and its +variants), tiles")
      ->capture_default_str();
  b.add_option("--fovea-effect", o.foveaEffect, "effect of the foveation group (the paper's middle sample count)")
      ->capture_default_str();
  b.add_option("--fovea-samples", o.foveaSamples, "sample count of the foveation group (0: the paper's middle count)")
      ->capture_default_str();
  b.add_option("--fovea-frames", o.foveaFrames,
               "frames per camera path of the motion runs, each with the path's previous frame (0: none)")
      ->capture_default_str();
}

void addSweepOptions(CLI::App& b, BenchCommand& c) {
  BenchOptions& o = c.options;
  b.add_option("--scenes", o.scenes, "scenes of the main sweep")->capture_default_str();
  b.add_option("--sizes", c.sizes, "sizes WxH of the main sweep (default 1280x720)");
  b.add_option("--effects", o.effects, "effects: ssao ssm ssgi")->capture_default_str();
  b.add_option(optionName(Param::Samples), o.samples,
               "sample counts of the main sweep (default: the paper's middle count, ssao 64, ssm 196, ssgi 288)");
  b.add_option("--methods", o.methods,
               "methods: " + methodNames(" and ") +
                   ", each with its variants' switches (mrr methods lists them), e.g. mrr-effect+c4+p0.3, mrr+norule")
      ->capture_default_str();
  b.add_option("--cameras", o.cameras, "cameras per scene (the paper: 8)")->capture_default_str();
  b.add_option("--repeats", o.repeats, "timed repeats per configuration")->capture_default_str();
  b.add_option(optionName(Param::Threads), o.threads, "the oracle's threads (0 = all cores)");
  b.add_flag("--no-sweeps", c.noSweeps, "skip the paper's sweeps (samples, resolution)");
  b.add_option("--sweep-size", c.sweepSize, "size of the samples sweep (default 1280x720)");
  b.add_option("--ssao-sweep", o.ssaoSweep, "SSAO sample counts of the samples sweep")->capture_default_str();
  b.add_option("--ssm-sweep", o.ssmSweep, "SSM sample counts of the samples sweep")->capture_default_str();
  b.add_option("--ssgi-sweep", o.ssgiSweep,
               "SSGI sample counts of the samples sweep (the paper's 1088 and 4224 take minutes per setting here)")
      ->capture_default_str();
  b.add_option("--resolutions", c.resolutions, "sizes of the resolution sweep (default 1280x720 1920x1080)");
  b.add_option("--frames", o.frames, "frames per camera path (0: no stability runs)")->capture_default_str();
  b.add_option("--stability-size", c.stabilitySize, "size of the camera-path frames (default 320x180)");
  b.add_option("--stability-scenes", o.stabilityScenes, "scenes of the camera paths")->capture_default_str();
  b.add_option("--stability-effects", o.stabilityEffects, "effects of the camera paths")->capture_default_str();
  b.add_option("--stress-scenes", o.stressScenes, "stress scenes")->capture_default_str();
  b.add_flag("--no-stress", c.noStress, "skip the stress scenes");
  b.add_option("--stress-size", c.stressSize, "size of the stress runs (default 1280x720)");
  addFoveaOptions(b, c);
}

void addOutputAndRuleOptions(CLI::App& b, BenchCommand& c) {
  BenchOptions& o = c.options;
  b.add_option("--json", o.jsonOut, "write every figure as JSON");
  b.add_option("--csv", o.csvOut, "write every run as CSV (and the stability table beside it, as NAME-stability.csv)");
  b.add_option("--markdown", o.markdownOut, "write the tables as Markdown");
  b.add_option("--report", o.reportDir, "write an HTML page with the charts, tables and images into DIR");
  b.add_flag("--check", o.check, "exit 1 when a sanity check fails");
  b.add_option("--calibrate", c.calibrateOut,
               "measure the never-slower rule's costs on each --paths path and write them as JSON (FILE, or FILE with "
               "{path} replaced)");
  b.add_option("--cold", o.coldRuns,
               "also render each main-sweep frame as a user does, in this many fresh `mrr render` processes per method "
               "(full, and tiles, mrr and mrr-effect where --methods has them, alternating), and report their speedup "
               "and process time (start to exit) beside the warm figures")
      ->check(CLI::Range(0, 100));
  b.add_option("--expectation", o.expectationSeeds,
               "for SSAO and SSGI, also measure each frame's error and each camera path's flicker against the effect's "
               "expectation: full's mean over this many other seeds (docs/spec.md section 10), beside the error against "
               "full's one draw (0: off)")
      ->check(CLI::Range(0, 256));
  b.add_option("--rule-sweep", c.ruleSweepOut,
               "check the never-slower rule on frames nobody tuned it to (shared, built-in and stress scenes; "
               "catalogue, default, sky and close-up views; 320x180 to 1920x1080) and write them as JSON "
               "(scripts/rule-chart.py draws it)");
  b.add_option("--rule-replay", c.ruleReplayIn,
               "re-decide every frame of a --rule-sweep JSON with this build's built-in cost models, from the counts "
               "it recorded, and judge them by the times it measured (renders nothing)");
  b.add_option(optionName(Param::CostModel), c.ruleCostModelFile,
               "with --rule-sweep or --rule-replay: the rule's costs, a JSON written by --calibrate ({path} is "
               "replaced by cpu or gpu; default: built in)");
  b.add_flag("--quick", c.quick,
             "minutes on 2 cores: builtin:demo and the arcade at 320x180, 2 cameras, 3 repeats, small sweeps, 8-frame "
             "paths at 96x54, stress scenes at 160x90, the foveation group on builtin:demo (rings at 640x360, ppd 30; 4-frame paths at 160x90); the oracle and, where EGL gives GL 3.3 core, the port (it says "
             "which on stderr; --paths chooses)");
}

// --quick: defaults for a run of minutes; options given explicitly still win.
void applyQuick(const CLI::App& b, BenchOptions& o) {
  const auto unset = [&](const std::string& option) { return b.count(option) == 0; };
  if (unset("--scenes")) o.scenes = {"builtin:demo", "arcade"};
  if (unset("--sizes")) o.sizes = {{320, 180}};
  if (unset(optionName(Param::Samples))) o.samples = {16};
  if (unset("--cameras")) o.cameras = 2;
  // three repeats: the median of one is too noisy for --check on a loaded 2-core machine
  if (unset("--repeats")) o.repeats = 3;
  if (unset("--sweep-size")) o.sweepSize = {160, 90};
  if (unset("--resolutions")) o.resolutions = {{96, 54}, {160, 90}};
  if (unset("--ssao-sweep")) o.ssaoSweep = {8, 16};
  if (unset("--ssm-sweep")) o.ssmSweep = {16, 36};
  if (unset("--ssgi-sweep")) o.ssgiSweep = {8, 16};
  if (unset("--frames")) o.frames = 8;
  if (unset("--stability-size")) o.stabilitySize = {96, 54};
  if (unset("--stability-scenes")) o.stabilityScenes = {"builtin:demo"};
  if (unset("--stress-size")) o.stressSize = {160, 90};
  // The foveation group: rings at a size where ppd 30 reaches level 1 (from 153 px) and, near the
  // corners, level 2 (from 335 px).
  if (unset("--fovea-scenes")) o.foveaScenes = {"builtin:demo"};
  if (unset("--fovea-size")) o.foveaSize = {640, 360};
  if (unset("--fovea-motion-size")) o.foveaMotionSize = {160, 90};
  if (unset("--fovea-ppd")) o.foveaPpds = {30.0};
  if (unset("--fovea-frames")) o.foveaFrames = 4;
  if (unset("--fovea-samples")) o.foveaSamples = 16;
}

// --quick without --paths: the port beside the oracle where a GL 3.3 core context can be made
// here, and one line on stderr saying which ran (and, for the oracle alone, why).
void quickPaths(const CLI::App& b, std::vector<std::string>& paths, std::ostream& err) {
  if (b.count("--paths") != 0) return;
  std::string why;
  if (gpu::glAvailable(&why)) {
    paths = {"cpu", "gpu"};
    err << "[bench] --quick: both paths, the oracle (cpu) and the port (gpu); --paths cpu for the oracle alone\n";
  } else {
    paths = {"cpu"};
    err << "[bench] --quick: the oracle (cpu) only: the port needs EGL with GL 3.3 core; here: " << why << "\n";
  }
}

// The sizes given as text, parsed; every size and sample count in range, every name known.
void resolveAndValidate(BenchCommand& c) {
  BenchOptions& o = c.options;
  if (!c.sizes.empty()) {
    o.sizes.clear();
    for (const auto& s : c.sizes) o.sizes.push_back(parseSize(s));
  }
  if (!c.resolutions.empty()) {
    o.resolutions.clear();
    for (const auto& s : c.resolutions) o.resolutions.push_back(parseSize(s));
  }
  if (!c.sweepSize.empty()) o.sweepSize = parseSize(c.sweepSize);
  if (!c.stabilitySize.empty()) o.stabilitySize = parseSize(c.stabilitySize);
  if (!c.stressSize.empty()) o.stressSize = parseSize(c.stressSize);
  o.paperSweeps = !c.noSweeps;
  if (c.noStress) o.stressScenes.clear();
  if (!c.foveaSize.empty()) o.foveaSize = parseSize(c.foveaSize);
  if (!c.foveaMotionSize.empty()) o.foveaMotionSize = parseSize(c.foveaMotionSize);
  o.fovea = !c.noFovea;
  require(!(c.noFovea && o.foveaOnly), "--fovea-only: not with --no-fovea");
  for (double ppd : o.foveaPpds)
    require(std::isfinite(ppd) && ppd > 0.0 && ppd <= 1.0e6, "--fovea-ppd " + std::to_string(ppd) + ": must be > 0");
  require(o.foveaFrames == 0 || (o.foveaFrames >= 2 && o.foveaFrames <= 10000), "--fovea-frames: must be 0 or in [2, 10000]");
  {
    Settings fs = defaultSettings(parseEffect(o.foveaEffect));  // validates the name and the count
    if (o.foveaSamples != 0) {
      fs.setSamples(o.foveaSamples);
      validateSettings(fs);
    }
  }
  std::string limited;  // the methods the level limit applies to: those whose masks come from the edges
  for (const MethodInfo& m : methods())
    if (m.findsEdges) limited += (limited.empty() ? "" : ", ") + std::string(m.name);
  for (const std::string& m : o.foveaMethods) {
    const Mode mode = settingsFor(m, Effect::Ssao, 64, 64, 16).mode;  // validates the name
    require(methodInfo(mode).findsEdges, "--fovea-methods " + m + ": the level limit (SPEC §13) applies to " + limited + " only");
  }
  require(o.repeats >= 1 && o.repeats <= 100, "--repeats: must be in [1, 100]");
  require(o.cameras >= 1 && o.cameras <= 64, "--cameras: must be in [1, 64]");
  require(o.frames == 0 || (o.frames >= 2 && o.frames <= 10000), "--frames: must be 0 or in [2, 10000]");
  std::vector<std::pair<int, int>> allSizes = o.sizes;
  allSizes.insert(allSizes.end(), o.resolutions.begin(), o.resolutions.end());
  for (const auto& sz : {o.sweepSize, o.stabilitySize, o.stressSize, o.foveaSize, o.foveaMotionSize}) allSizes.push_back(sz);
  for (const auto& [w, h] : allSizes)
    require(w >= 1 && h >= 1 && w <= kMaxImageSize && h <= kMaxImageSize,
            "--sizes " + std::to_string(w) + "x" + std::to_string(h) + ": each side must be in [1, " +
                std::to_string(kMaxImageSize) + "]");
  for (const std::string& m : o.methods) settingsFor(m, Effect::Ssao, 64, 64, 16);  // validates the name
  for (const std::string& e : o.stabilityEffects) parseEffect(e);  // validates the name
  // Every sample count in its effect's range: the main sweep's for each chosen effect, and
  // each effect's samples sweep.
  auto validateCounts = [](Effect effect, const std::vector<int>& counts) {
    Settings probeSettings = defaultSettings(effect);
    for (int n : counts) {
      probeSettings.setSamples(n);
      validateSettings(probeSettings);
    }
  };
  for (const std::string& e : o.effects) validateCounts(parseEffect(e), o.samples);
  validateCounts(Effect::Ssao, o.ssaoSweep);
  validateCounts(Effect::Ssm, o.ssmSweep);
  validateCounts(Effect::Ssgi, o.ssgiSweep);
  for (const std::string& p : c.paths)
    require(p == "cpu" || p == "gpu", "--paths " + p + ": unknown path (expected cpu or gpu)");
  require(o.threads >= 0 && o.threads <= 1024, "--threads: must be in [0, 1024]");
}

void checkOutputs(const BenchCommand& c) {
  const BenchOptions& o = c.options;
  if (!o.jsonOut.empty()) checkOutput(o.jsonOut, "--json", {".json"});
  if (!o.markdownOut.empty()) checkOutput(o.markdownOut, "--markdown", {".md"});
  if (!o.csvOut.empty()) checkOutput(o.csvOut, "--csv", {".csv"});
  if (!o.reportDir.empty()) {
    requireReportPython();  // before the folder is made: a missing package writes nothing
    makeReportDir(o.reportDir);
  }
  requireDistinct({{"--json", o.jsonOut}, {"--markdown", o.markdownOut}, {"--csv", o.csvOut}});
  require(c.ruleCostModelFile.empty() || !c.ruleSweepOut.empty() || !c.ruleReplayIn.empty(),
          optionName(Param::CostModel) + ": only with --rule-sweep or --rule-replay (the bench's methods run with the built-in rule)");
}

int calibrate(const BenchCommand& c, const std::vector<BenchPath>& paths, int threads) {
  for (const BenchPath& p : paths) {
    const std::string file = withPathName(c.calibrateOut, p.name);
    checkOutput(file, "--calibrate", {".json"});
    const CostModel model = calibrateCostModel(p, c.options.repeats, threads);
    writeTextFile(file, model.toJson().dump(2) + "\n");
    std::cout << p.name << ": " << model.toJson().dump() << "\n";
  }
  return 0;
}

int ruleSweep(const BenchCommand& c, const std::vector<BenchPath>& paths, int threads) {
  checkOutput(c.ruleSweepOut, "--rule-sweep", {".json"});
  RuleSweepOptions ro;
  ro.jsonOut = c.ruleSweepOut;
  ro.repeats = c.options.repeats;
  ro.threads = threads;
  ro.costModelFile = c.ruleCostModelFile;
  for (const BenchPath& p : paths) ruleCostModel(ro.costModelFile, p.name);  // a bad file fails before the sweep
  if (c.command->count("--scenes")) ro.scenes = c.options.scenes;
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  ro.machine = c.options.machine.empty() ? cpuModelName() + ", " + std::to_string(hw) + " hardware threads" : c.options.machine;
  return runRuleSweep(ro, paths, std::cout);
}

}  // namespace

void addBenchCommand(CLI::App& app, BenchCommand& c) {
  c.command = app.add_subcommand(
      "bench", "speed against accuracy: every method against full, side by side; charts, stability, stress scenes");
  c.command->add_option("--paths", c.paths, "cpu (the oracle) and/or gpu (the port)")->capture_default_str();
  c.command->add_option(optionName(Param::GlDevice), c.path.glDevice, "gpu: the EGL device index");
  c.command->add_option(optionName(Param::GpuTiming), c.path.gpuTiming, "gpu: auto, wall, query or passes (as render's --gpu-timing)")
      ->capture_default_str();
  addSweepOptions(*c.command, c);
  addOutputAndRuleOptions(*c.command, c);
}

int runBenchCommand(BenchCommand& c) {
  if (c.quick) applyQuick(*c.command, c.options);
  resolveAndValidate(c);
  checkOutputs(c);
  // After every check (bad input is one line, nothing before it, and fails before any GL is
  // tried); the bench's sweeps only, not --calibrate, --rule-sweep or --rule-replay, which keep
  // their own --paths.
  if (c.quick && c.ruleReplayIn.empty() && c.calibrateOut.empty() && c.ruleSweepOut.empty())
    quickPaths(*c.command, c.paths, std::cerr);
  if (!c.ruleReplayIn.empty())  // no path, no GL
    return replayRuleSweep(c.ruleReplayIn, c.ruleCostModelFile, c.options.jsonOut, std::cout);
  // The paths, each behind a RenderFn; the GL context is made once and shared by every scene.
  const int threads = threadCount(c.options.threads);
  std::vector<BenchPath> paths;
  for (const std::string& p : c.paths) paths.push_back(benchPath(p, threads, c.path));
  if (!c.calibrateOut.empty()) return calibrate(c, paths, threads);
  if (!c.ruleSweepOut.empty()) return ruleSweep(c, paths, threads);
  return runBench(c.options, paths, std::cout);
}

}  // namespace mrr
