#include "compare/bench/bench.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include <unistd.h>

#include "common/error.h"
#include "common/image_io.h"
#include "compare/bench/bench_format.h"
#include "compare/report/process.h"
#include "common/stages.h"
#include "compare/bench/bench_report.h"
#include "compare/metrics/metrics.h"
#include "compare/report/report.h"
#include "scenes/cameras.h"
#include "scenes/catalog.h"

namespace mrr {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

Settings settingsFor(const std::string& method, Effect effect, int w, int h, int samples) {
  Settings s = defaultSettings(effect);
  s.width = w;
  s.height = h;
  s.setSamples(samples);
  // A row of the method table with its bench switches (common/methods.h: "mrr-effect+c4+p0.15"),
  // each a frame parameter set as the command line sets it.
  const MethodSpec spec = parseMethodSpec(method);
  s.mode = spec.method->mode;
  for (const auto& [param, value] : spec.values) setParam(s, param, value);
  validateSettings(s);
  return s;
}

OpenScene openScene(const std::string& name, const BenchPath& path) {
  OpenScene o;
  o.name = name;
  SceneRequest req;
  req.scene = name;
  ResolvedScene rs = resolveScene(req);
  o.scene = std::make_unique<Scene>(std::move(rs.scene));
  o.camera = rs.camera;
  o.render = path.open(*o.scene);
  return o;
}

std::map<std::string, double> stageMs(const FrameResult& f) {
  std::map<std::string, double> perStage;
  for (const StageTiming& st : f.timings) perStage[st.stage] += st.ms;
  return perStage;
}

// The method's own time (docs/spec.md §10): the frame less the stages every method pays alike
// and that are not the effect: the full-res G-buffer, which a deferred renderer has anyway, and
// the shaded image for viewing (stage 6, the same pass over the final image for every method).
double effectMs(const std::map<std::string, double>& ms) {
  auto at = [&](Timed t, int level = -1) {
    const auto it = ms.find(timedName(t, level));
    return it != ms.end() ? it->second : 0.0;
  };
  return at(Timed::Total) - at(Timed::GBuffer, 0) - at(Timed::Shade);
}

namespace {

using bench_format::fixed;
using bench_format::sizeName;


int middleSamples(Effect e) { return e == Effect::Ssm ? 196 : e == Effect::Ssgi ? 288 : 64; }

// The effect's expectation (docs/spec.md §10): full's effect buffer averaged over seeds 1..K,
// each an independent draw of the same estimator (Settings::seed), untimed. Empty where K is 0
// or the effect draws no noise (SSM).
ImageF effectExpectation(const OpenScene& sc, const Camera& camera, const Settings& full, float framed, int seeds) {
  if (seeds <= 0 || !isStochastic(full.effect)) return {};
  ImageF sum;
  for (int k = 1; k <= seeds; ++k) {
    Settings s = full;
    s.seed = static_cast<uint32_t>(k);
    const FrameResult f = sc.render(camera, makeConstants(s, framed), {false, {}, nullptr});
    const ImageF& img = f.final();
    if (sum.empty()) sum = ImageF(img.width, img.height, img.channels, 0.0f);
    for (size_t i = 0; i < img.data.size(); ++i) sum.data[i] += img.data[i];
  }
  for (float& v : sum.data) v /= static_cast<float>(seeds);
  return sum;
}

struct Progress {
  size_t done = 0, total = 0;
  std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  void step(const std::string& what) {
    ++done;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "[bench] " << done << "/" << total << "  " << what << "  (" << fixed(s, 0) << " s)\n";
  }
};

class Sweep {
 public:
  Sweep(const BenchOptions& o, std::vector<BenchRecord>& records) : o_(o), records_(records) {}

  // Renders full and every method on one camera and setting, alternating, `repeats` times
  // after a warm-up, and records each. Returns the frames of the last repeat, by method.
  std::map<std::string, FrameResult> measure(const BenchPath& path, const OpenScene& sc, int cameraIndex,
                                             const Camera& camera, Effect effect, int w, int h, int samples,
                                             const std::vector<std::string>& methods, const std::string& group) {
    const std::string reference = referenceMethod();
    std::vector<std::string> all = {reference};
    for (const std::string& m : methods)
      if (m != reference) all.push_back(m);
    std::map<std::string, std::map<std::string, std::vector<double>>> stageRuns, passRuns;
    std::map<std::string, FrameResult> last;
    FrameResult firstFull;
    const float framed = framedSize(*sc.scene, camera, static_cast<float>(w) / static_cast<float>(h)).size;
    for (int i = 0; i <= o_.repeats; ++i)
      for (const std::string& m : all) {
        const Constants c = makeConstants(settingsFor(m, effect, w, h, samples), framed);
        FrameResult f = sc.render(camera, c, {false, {}, nullptr});
        if (i == 0) {  // warm-up; full's is kept to check that repeats give the same bits
          if (m == reference) firstFull = std::move(f);
          continue;
        }
        for (const auto& [k, v] : stageMs(f)) stageRuns[m][k].push_back(v);
        for (const PassTiming& p : f.passTimings) passRuns[m][p.stage + " " + p.pass].push_back(p.ms);
        if (i == o_.repeats) last[m] = std::move(f);
      }
    const std::map<std::string, ColdFrame> cold = group == "main" && o_.coldRuns > 0
                                                      ? coldFrames(path, sc, camera, effect, w, h, samples, all)
                                                      : std::map<std::string, ColdFrame>{};
    const FrameResult& full = last.at(reference);
    const ImageF expectation = group == "main" ? effectExpectation(sc, camera, settingsFor(reference, effect, w, h, samples),
                                                                   framed, o_.expectationSeeds)
                                               : ImageF{};  // the main sweep's frames only
    std::map<std::string, double> fullMedian;
    for (const auto& [k, v] : stageRuns[reference]) fullMedian[k] = median(v);
    const double fullEffect = effectMs(fullMedian);
    for (const std::string& m : all) {
      BenchRecord r;
      r.path = path.name;
      r.scene = sc.name;
      r.camera = cameraIndex;
      r.group = group;
      r.method = m;
      r.effect = toString(effect);
      r.width = w;
      r.height = h;
      r.samples = samples;
      for (const auto& [k, v] : stageRuns[m]) r.stageMs[k] = median(v);
      for (const auto& [k, v] : passRuns[m]) r.passMs[k] = median(v);
      r.effectMs = effectMs(r.stageMs);
      r.totalMs = r.stageMs[timedName(Timed::Total)];
      const FrameResult& f = last.at(m);
      r.shadedPixels = f.shadedPixelsTotal;
      r.idealSpeedup = f.idealSpeedup;
      r.idealSpeedupHit = f.idealSpeedupHit;
      r.measuredSpeedup = fullEffect / std::max(r.effectMs, 1e-9);
      r.fullEffectMs = fullEffect;
      if (cold.count(m) && cold.count(reference)) {
        r.coldEffectMs = cold.at(m).effectMs;
        r.coldSpeedup = cold.at(reference).effectMs / std::max(cold.at(m).effectMs, 1e-9);
        r.coldProcessMs = cold.at(m).processMs;
      }
      r.fellBack = f.fallback.fellBack;
      // full against its own warm-up frame: 0 exactly when repeats give the same bits
      const FrameErrors e = errorVsFull(f, m == reference ? firstFull : full);
      r.error = e.effect;
      r.shadedRms = e.shaded.rms;
      r.flip = e.effectFlip.mean;
      r.shadedFlip = e.shadedFlip.mean;
      if (!expectation.empty()) {
        r.expectationRms = rmsError(f.final(), expectation);
        r.expectationMae = meanAbsError(f.final(), expectation);
      }
      records_.push_back(r);
    }
    return last;
  }

 private:
  // A cold single frame's medians: its effect time (effectMs of its report's timings) and the
  // process's wall time, start to exit.
  struct ColdFrame {
    double effectMs = 0.0, processMs = 0.0;
  };
  // Fresh `mrr render` processes of full and of each of `methods` the method table marks `cold`, alternating,
  // o_.coldRuns each: their medians by method.
  std::map<std::string, ColdFrame> coldFrames(const BenchPath& path, const OpenScene& sc, const Camera& camera,
                                              Effect effect, int w, int h, int samples,
                                              const std::vector<std::string>& methods) const {
    const std::string self = selfExecutable();
    if (self.empty()) throw MrrError("bench --cold: cannot find this executable (/proc/self/exe)");
    const std::string dir = (std::filesystem::temp_directory_path() / ("mrr-cold-" + std::to_string(getpid()))).string();
    std::filesystem::create_directories(dir);
    auto vec = [](const glm::vec3& v) { return fixed(v.x, 6) + "," + fixed(v.y, 6) + "," + fixed(v.z, 6); };
    std::vector<std::string> cold = {referenceMethod()};
    const std::vector<std::string> coldRows = coldMethods();  // the method table's `cold` rows
    for (const std::string& m : methods)
      if (std::find(coldRows.begin(), coldRows.end(), parseMethodSpec(m).method->name) != coldRows.end()) cold.push_back(m);
    std::map<std::string, std::vector<double>> effectRuns, processRuns;
    for (int i = 0; i < o_.coldRuns; ++i)
      for (const std::string& m : cold) {
        const std::string report = dir + "/report.json";
        const auto option = [](Param p) { return optionName(p); };
        std::vector<std::string> args = {self, "render", option(Param::Scene), sc.name, option(Param::Path), path.name,
                                         option(Param::Size), sizeName(w, h), option(Param::Effect), toString(effect),
                                         option(Param::Samples), std::to_string(samples),
                                         option(Param::Eye), vec(camera.eye), option(Param::Target), vec(camera.target),
                                         option(Param::Up), vec(camera.up),
                                         option(Param::Fov), fixed(camera.yfov * 180.0 / 3.14159265358979323846, 6),
                                         "--report", report, "-q"};
        for (const std::string& a : methodSpecArgs(parseMethodSpec(m))) args.push_back(a);
        if (path.name == "cpu" && o_.threads > 0) args.insert(args.end(), {option(Param::Threads), std::to_string(o_.threads)});
        std::string why;
        const auto start = std::chrono::steady_clock::now();
        const int rc = runProcess(args, dir + "/log.txt", why);
        processRuns[m].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        if (rc != 0) throw MrrError("bench --cold: mrr render exited " + std::to_string(rc) + (why.empty() ? "" : ": " + why));
        std::ifstream in(report);
        const nlohmann::json j = nlohmann::json::parse(in);
        effectRuns[m].push_back(effectMs(j.at("timings_ms").get<std::map<std::string, double>>()));
      }
    std::filesystem::remove_all(dir);
    std::map<std::string, ColdFrame> out;
    for (const auto& [m, v] : effectRuns) out[m] = {median(v), median(processRuns.at(m))};
    return out;
  }

  const BenchOptions& o_;
  std::vector<BenchRecord>& records_;
};

void writeExampleImages(const std::string& dir, const std::map<std::string, FrameResult>& frames) {
  std::filesystem::create_directories(dir);
  const FrameResult& full = frames.at(referenceMethod());
  for (const auto& [m, f] : frames) {
    writeImage(dir + "/" + m + ".png", f.final(), {}, false);
    writeImage(dir + "/" + m + "-shaded.png", f.shaded, {}, true);
    ImageF diff(f.final().width, f.final().height, 1);
    for (int y = 0; y < diff.height; ++y)
      for (int x = 0; x < diff.width; ++x) {
        float d = 0.0f;
        for (int ch = 0; ch < f.final().channels; ++ch) d = std::max(d, std::abs(f.final().at(x, y, ch) - full.final().at(x, y, ch)));
        diff.at(x, y) = std::min(1.0f, 10.0f * d);
      }
    writeImage(dir + "/" + m + "-diff10.png", diff, {}, false);
  }
}

std::vector<Effect> parseEffects(const std::vector<std::string>& names) {
  std::vector<Effect> out;
  for (const std::string& e : names) out.push_back(parseEffect(e));
  return out;
}

}  // namespace

std::string cpuModelName() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpu, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

int runBench(const BenchOptions& optionsIn, const std::vector<BenchPath>& paths, std::ostream& out) {
  BenchOptions o = optionsIn;
  if (o.foveaOnly) {  // the foveation group alone
    o.scenes.clear();
    o.paperSweeps = false;
    o.frames = 0;
    o.stressScenes.clear();
  }
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = o.threads > 0 ? o.threads : hw;
  if (o.machine.empty()) o.machine = cpuModelName() + ", " + std::to_string(hw) + " hardware threads";
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  const std::vector<Effect> effects = parseEffects(o.effects);
  std::vector<BenchRecord> records;
  std::vector<StabilityRecord> stability;
  Sweep sweep(o, records);
  std::map<std::string, std::string> devices;
  for (const BenchPath& p : paths) devices[p.name] = p.device;

  // Count the steps for the progress lines.
  Progress progress;
  const size_t perPath = o.scenes.size() * static_cast<size_t>(o.cameras) * o.sizes.size() *
                         (o.samples.empty() ? effects.size() : effects.size() * o.samples.size());
  size_t sweeps = 0;
  if (o.paperSweeps) {
    for (Effect e : effects) sweeps += (e == Effect::Ssao ? o.ssaoSweep : e == Effect::Ssm ? o.ssmSweep : o.ssgiSweep).size();
    sweeps += effects.size() * o.resolutions.size();
  }
  const size_t stab = o.frames > 0 ? o.stabilityScenes.size() * o.stabilityEffects.size() * cameraPathKinds().size() : 0;
  const size_t stress = o.stressScenes.size() * effects.size();
  progress.total = paths.size() * (perPath + sweeps + stab + stress);
  FoveaResults fovea;

  std::string examplesDone;
  for (const BenchPath& path : paths) {
    // 1. The main sweep: every method on every scene, camera, size, effect and sample count.
    for (const std::string& sceneName : o.scenes) {
      std::cerr << "[bench] " << path.name << ": loading " << sceneName << "\n";
      const OpenScene sc = openScene(sceneName, path);
      const std::vector<Camera> cams = benchCameras(sc.camera, o.cameras);
      for (int ci = 0; ci < o.cameras; ++ci)
        for (const auto& [w, h] : o.sizes)
          for (Effect e : effects) {
            const std::vector<int> counts = o.samples.empty() ? std::vector<int>{middleSamples(e)} : o.samples;
            for (int n : counts) {
              progress.step(path.name + " " + sceneName + " camera " + std::to_string(ci) + " " + sizeName(w, h) + " " +
                            toString(e) + "-" + std::to_string(n));
              const auto frames = sweep.measure(path, sc, ci, cams[static_cast<size_t>(ci)], e, w, h, n, o.methods, "main");
              // Example images of each method on the same frame, once per path and effect.
              const std::string key = path.name + "/" + toString(e);
              if (!o.reportDir.empty() && examplesDone.find("[" + key + "]") == std::string::npos) {
                writeExampleImages(o.reportDir + "/images/" + path.name + "-" + toString(e), frames);
                examplesDone += "[" + key + "]";
              }
            }
          }
    }
    // 2. The paper's sweeps on the first scene's first camera.
    if (o.paperSweeps && !o.scenes.empty()) {
      const OpenScene sc = openScene(o.scenes.front(), path);
      for (Effect e : effects) {
        const std::vector<int>& counts = e == Effect::Ssao ? o.ssaoSweep : e == Effect::Ssm ? o.ssmSweep : o.ssgiSweep;
        for (int n : counts) {
          progress.step(path.name + " samples sweep " + sc.name + " " + sizeName(o.sweepSize.first, o.sweepSize.second) +
                        " " + toString(e) + "-" + std::to_string(n));
          sweep.measure(path, sc, 0, sc.camera, e, o.sweepSize.first, o.sweepSize.second, n, o.methods, "samples");
        }
        for (const auto& [w, h] : o.resolutions) {
          progress.step(path.name + " resolution sweep " + sc.name + " " + sizeName(w, h) + " " + toString(e) + "-" +
                        std::to_string(middleSamples(e)));
          sweep.measure(path, sc, 0, sc.camera, e, w, h, middleSamples(e), o.methods, "resolution");
        }
      }
    }
    // 3. Stability along camera paths: flicker of every method against full, frame by frame.
    if (o.frames > 0)
      for (const std::string& sceneName : o.stabilityScenes) {
        const OpenScene sc = openScene(sceneName, path);
        // The radii of the path's first view, kept along it (as a camera moving through a scene keeps them).
        const auto [sw, sh] = o.stabilitySize;
        const float framed = framedSize(*sc.scene, sc.camera, static_cast<float>(sw) / static_cast<float>(sh)).size;
        for (const std::string& effectName : o.stabilityEffects)
          for (const std::string& kind : cameraPathKinds()) {
            const Effect e = parseEffect(effectName);
            progress.step(path.name + " stability " + sceneName + " " + kind + " " + std::to_string(o.frames) + " frames " +
                          effectName);
            std::map<std::string, FlickerMeter> meters;
            // against the expectation: flicker and mean RMS, no FLIP; full's own row among them
            std::map<std::string, FlickerMeter> expected;
            const auto againstExpectation = [&](const std::string& m, const ImageF& frame, const ImageF& expectation) {
              expected.try_emplace(m, false).first->second.add(frame, expectation);
            };
            // SPEC §14: each method's frames in sequence, each reading what the previous one left
            // (a method whose temporal term is off leaves nothing, and reads nothing).
            std::map<std::string, FrameHistory> histories;
            const auto [w, h] = o.stabilitySize;
            for (const Camera& cam : cameraPath(sc.camera, kind, o.frames)) {
              const Settings fullSettings = settingsFor(referenceMethod(), e, w, h, middleSamples(e));
              const FrameResult full = sc.render(cam, makeConstants(fullSettings, framed), {false, {}, nullptr});
              const ImageF expectation = effectExpectation(sc, cam, fullSettings, framed, o.expectationSeeds);
              if (!expectation.empty()) againstExpectation(referenceMethod(), full.final(), expectation);
              for (const std::string& m : o.methods) {
                if (m == referenceMethod()) continue;
                RenderOptions options{false, {}, nullptr};
                FrameHistory& history = histories[m];
                if (!history.empty()) options.history = &history;
                FrameResult f = sc.render(cam, makeConstants(settingsFor(m, e, w, h, middleSamples(e)), framed), options);
                meters[m].add(f.final(), full.final());
                if (!expectation.empty()) againstExpectation(m, f.final(), expectation);
                history = std::move(f.history);
              }
            }
            // full's own row, beside its expectation only: against itself every figure is 0
            if (expected.count(referenceMethod())) meters.try_emplace(referenceMethod());
            for (const auto& [m, meter] : meters) {
              StabilityRecord r{path.name, sceneName, effectName, middleSamples(e), kind, o.frames, w, h, m,
                                meter.flicker(), meter.meanRms(), meter.flipFlicker(), meter.meanFlip()};
              if (expected.count(m)) {
                r.expectationFlicker = expected.at(m).flicker();
                r.expectationMeanRms = expected.at(m).meanRms();
              }
              stability.push_back(r);
            }
          }
      }
    // 4. The stress scenes: every method, and the paper's without the never-slower rule.
    for (const std::string& sceneName : o.stressScenes) {
      const OpenScene sc = openScene(sceneName, path);
      std::vector<std::string> methods = o.methods;
      if (std::find(methods.begin(), methods.end(), toString(Mode::Mrr)) != methods.end())
        methods.push_back(toString(Mode::Mrr) + "+norule");
      for (Effect e : effects) {
        progress.step(path.name + " stress " + sceneName + " " + toString(e));
        sweep.measure(path, sc, 0, sc.camera, e, o.stressSize.first, o.stressSize.second, middleSamples(e), methods,
                      "stress");
      }
    }
    // 5. Foveation and motion (SPEC §13): compare/bench/bench_fovea.cpp.
    runFoveaGroup(o, path, fovea);
  }

  BenchResults results{o, devices, records, stability, threads, std::move(fovea)};
  const std::vector<std::string> failures = sanityChecks(results);
  const std::string md = benchMarkdown(results, failures);
  out << md;
  if (!o.markdownOut.empty()) writeTextFile(o.markdownOut, md);
  if (!o.jsonOut.empty()) writeTextFile(o.jsonOut, benchJson(results, failures).dump(1) + "\n");
  if (!o.csvOut.empty()) writeTextFile(o.csvOut, benchCsv(results));
  if (!o.csvOut.empty() && !stability.empty()) writeTextFile(stabilityCsvPath(o.csvOut), benchStabilityCsv(results));
  if (!o.csvOut.empty() && !results.fovea.rings.empty())
    writeTextFile(foveaCsvPath(o.csvOut, "-fovea"), foveaRingsCsv(results.fovea));
  if (!o.csvOut.empty() && !results.fovea.motion.empty())
    writeTextFile(foveaCsvPath(o.csvOut, "-fovea-motion"), foveaMotionCsv(results.fovea));
  if (!o.reportDir.empty()) {
    std::cerr << "[bench] writing the report to " << o.reportDir << "\n";
    writeBenchReport(o.reportDir, results, failures);
  }
  for (const std::string& f : failures) std::cerr << "[bench] sanity check failed: " << f << "\n";
  return o.check && !failures.empty() ? 1 : 0;
}

}  // namespace mrr
