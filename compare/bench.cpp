#include "compare/bench.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <thread>
#include <tuple>

#include "common/image_io.h"
#include "compare/report.h"
#include "scenes/catalog.h"

namespace mrr {

namespace {

struct Timed {
  FrameResult frame;                        // the last repeat's frame
  std::map<std::string, double> medianMs;   // per stage (and "total")
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Renders the two modes alternately, `repeats` times each after one warm-up of each, so
// that drift in the machine (other load, frequency, memory) hits both alike; the ratio of
// medians is then a side-by-side figure.
std::pair<Timed, Timed> timedPair(const Renderer& r, const Camera& cam, const Constants& a, const Constants& b,
                                  int repeats) {
  Timed ta, tb;
  std::map<std::string, std::vector<double>> sa, sb;
  for (int i = 0; i <= repeats; ++i)
    for (auto [c, t, s] : {std::tuple{&a, &ta, &sa}, std::tuple{&b, &tb, &sb}}) {
      FrameResult f = r.render(cam, *c, {false, {}});
      if (i == 0) continue;  // warm-up
      std::map<std::string, double> perStage;
      for (const StageTiming& st : f.timings) perStage[st.stage] += st.ms;
      for (const auto& [k, v] : perStage) (*s)[k].push_back(v);
      if (i == repeats) t->frame = std::move(f);  // keep only the last: the heap stays one frame big
    }
  for (auto& [k, v] : sa) ta.medianMs[k] = median(v);
  for (auto& [k, v] : sb) tb.medianMs[k] = median(v);
  return {std::move(ta), std::move(tb)};
}

// The method's own cost: everything but the full-res G-buffer, which a deferred renderer
// has anyway and both modes share.
double effectMs(const std::map<std::string, double>& ms) {
  const auto total = ms.find("total"), g0 = ms.find("gbuffer.L0");
  return total->second - (g0 != ms.end() ? g0->second : 0.0);
}

std::string machineName() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpu, line))
    if (line.rfind("model name", 0) == 0) {
      const auto p = line.find(':');
      return line.substr(p + 2);
    }
  return "unknown CPU";
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

int runBench(const BenchOptions& o, std::ostream& out) {
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = o.threads > 0 ? o.threads : hw;
  nlohmann::json runs = nlohmann::json::array();
  std::ostringstream md;
  md << "Machine: " << machineName() << ", " << hw << " hardware threads; oracle (cpu_ref), " << threads
     << " threads; median of " << o.repeats << " repeats after 1 warm-up, full and multires alternating.\n"
     << "Effect time = frame time minus the full-res G-buffer (shared by both modes). "
     << "Measured speedup = full effect time / multires effect time; ideal = W*H / shaded pixels.\n\n";
  md << "| scene | effect | size | samples | full ms | multires ms | measured | ideal | measured/ideal | RMS | PSNR | SSIM | edge-band RMS | Mrays/s |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::ostringstream stagesMd, scalingMd;
  stagesMd << "| scene | effect | size | samples | mode | stage medians (ms) |\n|---|---|---|---|---|---|\n";
  scalingMd << "| scene | effect | size | samples | mode | 1 thread ms | " << threads
            << " threads ms | scaling |\n|---|---|---|---|---|---|---|---|\n";
  auto samplesFor = [&](Effect e) {
    if (!o.samples.empty()) return o.samples;
    switch (e) {
      case Effect::Ssm: return std::vector<int>{100, 196, 324};
      case Effect::Ssgi: return std::vector<int>{24, 80, 288};
      case Effect::Ssao: break;
    }
    return std::vector<int>{16, 64, 256};
  };
  std::vector<Effect> effects;
  for (const std::string& e : o.effects) effects.push_back(parseEffect(e));
  size_t perScene = 0;
  for (Effect e : effects) perScene += samplesFor(e).size();

  const size_t totalSteps = o.scenes.size() * o.sizes.size() * perScene;
  size_t step = 0;
  for (const std::string& sceneName : o.scenes) {
    SceneRequest req;
    req.scene = sceneName;
    std::cerr << "[bench] loading " << sceneName << "\n";
    ResolvedScene rs = resolveScene(req);
    std::unique_ptr<Renderer> renderer;
    {
      tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
      renderer = std::make_unique<Renderer>(rs.scene);
    }
    const float diag = rs.scene.bounds().diagonal();
    for (Effect effect : effects)
    for (const auto& [w, h] : o.sizes) {
      const std::vector<int> counts = samplesFor(effect);
      for (int n : counts) {
        ++step;
        const std::string eff = toString(effect);
        std::cerr << "[bench] " << step << "/" << totalSteps << "  " << sceneName << " " << w << "x" << h << " " << eff
                  << "-" << n << "\n";
        Settings s = defaultSettings(effect);
        s.width = w;
        s.height = h;
        s.setSamples(n);
        Settings sFull = s;
        sFull.mode = Mode::Full;
        const Constants cm = makeConstants(s, diag), cf = makeConstants(sFull, diag);
        Timed full, multi;
        {
          tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
          std::tie(full, multi) = timedPair(*renderer, rs.camera, cf, cm, o.repeats);
        }
        const ErrorFigures err = errorVsFull(multi.frame, full.frame).effect;
        const double fullMs = effectMs(full.medianMs), multiMs = effectMs(multi.medianMs);
        const double measured = fullMs / multiMs, ideal = multi.frame.idealSpeedup;
        const double rays = static_cast<double>(cf.paddedWidth) * cf.paddedHeight;
        const double mrays = rays / (full.medianMs["gbuffer.L0"] * 1e3);
        md << "| " << sceneName << " | " << eff << " | " << w << "x" << h << " | " << n << " | " << fixed(fullMs, 1) << " | "
           << fixed(multiMs, 1) << " | " << fixed(measured, 2) << "x | " << fixed(ideal, 2) << "x | "
           << fixed(100.0 * measured / ideal, 0) << "% | " << fixed(err.rms, 5) << " | " << fixed(err.psnr, 1) << " | "
           << fixed(err.ssim, 4) << " | " << fixed(err.edgeBandRms, 5) << " | " << fixed(mrays, 1) << " |\n";
        for (const Timed* t : {&full, &multi}) {
          stagesMd << "| " << sceneName << " | " << eff << " | " << w << "x" << h << " | " << n << " | "
                   << toString(t->frame.constants.mode) << " | ";
          for (const StageTiming& st : t->frame.timings) stagesMd << st.stage << " " << fixed(t->medianMs.at(st.stage), 1) << "; ";
          stagesMd << "|\n";
        }
        nlohmann::json run = {{"scene", sceneName}, {"effect", eff}, {"width", w}, {"height", h}, {"samples", n},
                              {"threads", threads}, {"repeats", o.repeats},
                              {"full_ms", full.medianMs}, {"multires_ms", multi.medianMs},
                              {"full_effect_ms", fullMs}, {"multires_effect_ms", multiMs},
                              {"measured_speedup", measured}, {"ideal_speedup", ideal},
                              {"shaded_pixels", multi.frame.shadedPixelsTotal}, {"primary_mrays_per_s", mrays},
                              {"rms", err.rms}, {"psnr", err.psnr}, {"ssim", err.ssim}, {"max_abs", err.maxAbs},
                              {"edge_band_rms", err.edgeBandRms}};
        if (o.scaling && n == counts[counts.size() / 2] && threads > 1) {
          std::cerr << "[bench]   thread scaling 1 vs " << threads << "\n";
          Timed full1, multi1;
          {
            tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
            std::tie(full1, multi1) = timedPair(*renderer, rs.camera, cf, cm, o.repeats);
          }
          for (auto [name, one, many] : {std::tuple{"full", &full1, &full}, std::tuple{"multires", &multi1, &multi}}) {
            const double t1 = one->medianMs.at("total"), tn = many->medianMs.at("total");
            scalingMd << "| " << sceneName << " | " << eff << " | " << w << "x" << h << " | " << n << " | " << name << " | "
                      << fixed(t1, 1) << " | " << fixed(tn, 1) << " | " << fixed(t1 / tn, 2) << "x |\n";
            run[std::string("scaling_") + name] = {{"one_thread_ms", t1}, {"n_threads_ms", tn}};
          }
        }
        runs.push_back(run);
      }
    }
  }
  std::ostringstream all;
  all << md.str() << "\nPer-stage medians:\n\n" << stagesMd.str() << "\nThread scaling (frame total):\n\n" << scalingMd.str();
  out << all.str();
  if (!o.markdownOut.empty()) writeTextFile(o.markdownOut, all.str());
  if (!o.jsonOut.empty())
    writeTextFile(o.jsonOut, nlohmann::json({{"machine", machineName()}, {"runs", runs}}).dump(2) + "\n");
  return 0;
}

}  // namespace mrr
