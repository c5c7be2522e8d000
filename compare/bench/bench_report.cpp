#include "compare/bench/bench_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "common/error.h"
#include "common/image_io.h"
#include "common/paths.h"
#include "compare/bench/bench_format.h"
#include "compare/report/report_python.h"

namespace mrr {

namespace {

using bench_format::fixed;
using bench_format::sci;
using bench_format::sizeName;

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The order methods are shown in: their rows' chart order (common/methods.h); a method's
// variants ("mrr-effect+c4+p0.3", "mrr+norule") follow it, by name.
int methodRank(const std::string& spec) {
  const MethodInfo* row = findMethod(std::string_view(spec).substr(0, spec.find('+')));
  return row ? row->chartOrder : 1000;
}

template <class T, class Key>
std::vector<Key> distinct(const std::vector<T>& items, std::function<Key(const T&)> key) {
  std::vector<Key> out;
  for (const T& t : items) {
    const Key k = key(t);
    if (std::find(out.begin(), out.end(), k) == out.end()) out.push_back(k);
  }
  return out;
}

std::vector<std::string> methodsOf(const std::vector<BenchRecord>& rs) {
  std::vector<std::string> m = distinct<BenchRecord, std::string>(rs, [](const BenchRecord& r) { return r.method; });
  std::sort(m.begin(), m.end(), [](const std::string& a, const std::string& b) {
    const auto rank = [](const std::string& x) { return methodRank(x); };
    return rank(a) != rank(b) ? rank(a) < rank(b) : a < b;
  });
  return m;
}

std::vector<BenchRecord> select(const std::vector<BenchRecord>& rs, const std::function<bool(const BenchRecord&)>& keep) {
  std::vector<BenchRecord> out;
  for (const BenchRecord& r : rs)
    if (keep(r)) out.push_back(r);
  return out;
}

// A Markdown table that the HTML page also shows (one source for both: report.py gets its rows).
struct Table {
  std::string title;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string markdown() const {
    std::ostringstream o;
    o << "### " << title << "\n\n|";
    // a | inside a cell ("max |Δ|") is escaped, or Markdown reads it as a column
    const auto cell = [](std::string c) {
      for (size_t i = c.find('|'); i != std::string::npos; i = c.find('|', i + 2)) c.insert(i, "\\");
      return c;
    };
    for (const auto& h : header) o << " " << cell(h) << " |";
    o << "\n|";
    for (size_t i = 0; i < header.size(); ++i) o << "---|";
    o << "\n";
    for (const auto& r : rows) {
      o << "|";
      for (const auto& c : r) o << " " << cell(c) << " |";
      o << "\n";
    }
    return o.str() + "\n";
  }
};

const PaperFigure* findPaper(const std::vector<PaperFigure>& paper, const std::string& figure, const std::string& effect,
                             int samples, int height) {
  for (const PaperFigure& p : paper)
    if (p.figure == figure && p.effect == effect && (samples == 0 || p.samples == samples) && (height == 0 || p.height == height))
      return &p;
  return nullptr;
}

// Calls `row` once per path × effect × sample count × method of the main sweep's records `main`
// that has records, with them (over every scene and camera), in the tables' order.
void perSetting(const std::vector<BenchRecord>& main,
                const std::function<void(const std::string& path, const std::string& effect, int samples,
                                         const std::string& method, const std::vector<BenchRecord>& sel)>& row) {
  for (const std::string& path : distinct<BenchRecord, std::string>(main, [](const BenchRecord& r) { return r.path; }))
    for (const std::string& effect : distinct<BenchRecord, std::string>(main, [](const BenchRecord& r) { return r.effect; }))
      for (int samples : distinct<BenchRecord, int>(main, [](const BenchRecord& r) { return r.samples; }))
        for (const std::string& m : methodsOf(main)) {
          const auto sel = select(main, [&](const BenchRecord& r) {
            return r.path == path && r.effect == effect && r.samples == samples && r.method == m;
          });
          if (!sel.empty()) row(path, effect, samples, m, sel);
        }
}

// Every table, in the order the page and the Markdown show them.
std::vector<Table> tables(const BenchResults& res, const std::vector<PaperFigure>& paper) {
  std::vector<Table> out;
  const auto& rs = res.records;
  // 1. The main sweep, per path × effect × method, over every scene and camera.
  {
    Table t{"Speed against accuracy: every scene and camera (medians; chart 1)",
            {"path", "effect", "samples", "method", "settings", "measured speedup", "ideal speedup", "measured/ideal",
             "RMS", "FLIP", "shaded FLIP", "PSNR", "SSIM", "edge-band RMS", "max |Δ|", "fell back", "effect ms"},
            {}};
    const auto main = select(rs, [](const BenchRecord& r) { return r.group == "main"; });
    perSetting(main, [&](const std::string& path, const std::string& effect, int samples, const std::string& m,
                         const std::vector<BenchRecord>& sel) {
            std::vector<double> meas, ideal, rms, flipMean, shadedFlip, psnr, ssim, band, maxAbs, ms;
            int fell = 0;
            int64_t bandPixels = 0;
            for (const BenchRecord& r : sel) {
              bandPixels += r.error.edgeBandPixels;
              meas.push_back(r.measuredSpeedup);
              ideal.push_back(r.idealSpeedup);
              rms.push_back(r.error.rms);
              flipMean.push_back(r.flip);
              shadedFlip.push_back(r.shadedFlip);
              psnr.push_back(std::isfinite(r.error.psnr) ? r.error.psnr : 999.0);
              ssim.push_back(r.error.ssim);
              band.push_back(r.error.edgeBandRms);
              maxAbs.push_back(r.error.maxAbs);
              ms.push_back(r.effectMs);
              fell += r.fellBack;
            }
            const double mm = median(meas), mi = median(ideal);
            t.rows.push_back({path, effect, std::to_string(samples), m, std::to_string(sel.size()), fixed(mm, 2) + "x",
                              fixed(mi, 2) + "x", fixed(100.0 * mm / mi, 0) + "%", sci(median(rms)),
                              sci(median(flipMean)), sci(median(shadedFlip)), median(psnr) >= 999.0 ? "inf" : fixed(median(psnr), 1), fixed(median(ssim), 4),
                              bandPixels > 0 ? sci(median(band)) : "—", sci(median(maxAbs)), std::to_string(fell) + "/" + std::to_string(sel.size()),
                              fixed(median(ms), 1)});
    });
    out.push_back(t);
  }
  // 1b. Single frames: fresh `mrr render` processes beside the warm bench (--cold).
  {
    Table t{"Single frames: a cold `mrr render` per frame against the warm bench (medians)",
            {"path", "scene", "camera", "size", "effect", "method", "warm speedup", "cold speedup", "cold / warm",
             "warm effect ms", "cold effect ms", "cold process ms (start to exit)"},
            {}};
    for (const BenchRecord& r : select(rs, [](const BenchRecord& x) { return x.group == "main" && x.coldSpeedup > 0.0; }))
      t.rows.push_back({r.path, r.scene, std::to_string(r.camera), sizeName(r.width, r.height),
                        r.effect + "-" + std::to_string(r.samples), r.method, fixed(r.measuredSpeedup, 2) + "x",
                        fixed(r.coldSpeedup, 2) + "x", fixed(r.coldSpeedup / std::max(r.measuredSpeedup, 1e-9), 2),
                        fixed(r.effectMs, 1), fixed(r.coldEffectMs, 1), fixed(r.coldProcessMs, 0)});
    if (!t.rows.empty()) out.push_back(t);
  }
  // 2. Per scene (all cameras): where each method wins.
  {
    Table t{"Per scene (median over cameras)", {"path", "scene", "effect", "method", "measured", "ideal", "RMS", "FLIP", "SSIM"}, {}};
    const auto main = select(rs, [](const BenchRecord& r) { return r.group == "main" && r.method != referenceMethod(); });
    for (const std::string& path : distinct<BenchRecord, std::string>(main, [](const BenchRecord& r) { return r.path; }))
      for (const std::string& scene : distinct<BenchRecord, std::string>(main, [](const BenchRecord& r) { return r.scene; }))
        for (const std::string& effect : distinct<BenchRecord, std::string>(main, [](const BenchRecord& r) { return r.effect; }))
          for (const std::string& m : methodsOf(main)) {
            const auto sel = select(main, [&](const BenchRecord& r) {
              return r.path == path && r.scene == scene && r.effect == effect && r.method == m;
            });
            if (sel.empty()) continue;
            std::vector<double> meas, ideal, rms, flipMean, ssim;
            for (const BenchRecord& r : sel) {
              meas.push_back(r.measuredSpeedup);
              ideal.push_back(r.idealSpeedup);
              rms.push_back(r.error.rms);
              flipMean.push_back(r.flip);
              ssim.push_back(r.error.ssim);
            }
            t.rows.push_back({path, scene, effect, m, fixed(median(meas), 2) + "x", fixed(median(ideal), 2) + "x",
                              sci(median(rms)), sci(median(flipMean)), fixed(median(ssim), 4)});
          }
    out.push_back(t);
  }
  // 3. The paper's sweeps, mrr beside the paper's figure.
  for (const std::string group : {"samples", "resolution"}) {
    const bool bySamples = group == std::string("samples");
    Table t{bySamples ? "Speedup against samples (the paper's Fig. 6)"
                      : "Speedup and RMS against resolution (the paper's Figs. 7 and 9)",
            {"path", "scene", "effect", "size", "samples", "method", "measured", "ideal", "RMS", "paper speedup (GTX 1080)",
             "paper RMS", "fell back"},
            {}};
    for (const BenchRecord& r : select(rs, [&](const BenchRecord& x) { return x.group == group && x.method != referenceMethod(); })) {
      const PaperFigure* ps = findPaper(paper, bySamples ? "fig6" : "fig7", r.effect, r.samples, bySamples ? 0 : r.height);
      const PaperFigure* pr = bySamples ? nullptr : findPaper(paper, "fig9", r.effect, r.samples, r.height);
      const bool showPaper = r.method == toString(Mode::Mrr);  // the paper's figures beside the paper's method
      t.rows.push_back({r.path, r.scene, r.effect, sizeName(r.width, r.height), std::to_string(r.samples), r.method,
                        fixed(r.measuredSpeedup, 2) + "x", fixed(r.idealSpeedup, 2) + "x", sci(r.error.rms),
                        showPaper && ps ? fixed(ps->speedup, 2) + "x" + (bySamples ? " (4K)" : "") : "",
                        showPaper && pr ? sci(pr->rms) : "", r.fellBack ? "yes" : ""});
    }
    if (!t.rows.empty()) out.push_back(t);
  }
  // 4. Stability.
  if (!res.stability.empty()) {
    Table t{"Stability along camera paths (SPEC §10 flicker: mean |Δ error| frame to frame; FLIP flicker: mean |Δ FLIP| "
            "frame to frame)",
            {"path", "scene", "effect", "camera path", "frames", "size", "method", "flicker", "mean RMS", "FLIP flicker",
             "mean FLIP"},
            {}};
    for (const StabilityRecord& s : res.stability)
      t.rows.push_back({s.path, s.scene, s.effect + "-" + std::to_string(s.samples), s.kind, std::to_string(s.frames),
                        sizeName(s.width, s.height), s.method, sci(s.flicker), sci(s.meanRms), sci(s.flipFlicker),
                        sci(s.meanFlip)});
    out.push_back(t);
  }
  // 4b. Against the effect's expectation (--expectation K, SPEC §10): the error a method adds to
  // the estimator's own, beside the error against full's one draw of it.
  {
    Table t{"Error against the effect's expectation (SPEC §10: full's mean over K other seeds; full's own row is the "
            "estimator's noise; medians over every scene and camera)",
            {"path", "effect", "samples", "method", "settings", "RMS against full", "RMS against the expectation",
             "mean |Δ| against the expectation", "measured speedup"},
            {}};
    const auto main = select(rs, [](const BenchRecord& r) { return r.group == "main" && std::isfinite(r.expectationRms); });
    perSetting(main, [&](const std::string& path, const std::string& effect, int samples, const std::string& m,
                         const std::vector<BenchRecord>& sel) {
            std::vector<double> rms, erms, emae, meas;
            for (const BenchRecord& r : sel) {
              rms.push_back(r.error.rms);
              erms.push_back(r.expectationRms);
              emae.push_back(r.expectationMae);
              meas.push_back(r.measuredSpeedup);
            }
            t.rows.push_back({path, effect, std::to_string(samples), m, std::to_string(sel.size()), sci(median(rms)),
                              sci(median(erms)), sci(median(emae)), fixed(median(meas), 2) + "x"});
    });
    if (!t.rows.empty()) out.push_back(t);
  }
  if (std::any_of(res.stability.begin(), res.stability.end(),
                  [](const StabilityRecord& s) { return std::isfinite(s.expectationFlicker); })) {
    Table t{"Stability against the effect's expectation (SPEC §10 flicker with the expectation for full; full's row is "
            "the estimator's own)",
            {"path", "scene", "effect", "camera path", "frames", "size", "method", "flicker against full",
             "flicker against the expectation", "mean RMS against the expectation"},
            {}};
    for (const StabilityRecord& s : res.stability)
      if (std::isfinite(s.expectationFlicker))
        t.rows.push_back({s.path, s.scene, s.effect + "-" + std::to_string(s.samples), s.kind, std::to_string(s.frames),
                          sizeName(s.width, s.height), s.method, sci(s.flicker), sci(s.expectationFlicker),
                          sci(s.expectationMeanRms)});
    out.push_back(t);
  }
  // 5. Stress scenes.
  {
    Table t{"Stress scenes: how coverage, speed and error degrade",
            {"path", "scene", "effect", "method", "shaded pixels / W·H", "ideal", "measured", "RMS", "edge-band RMS",
             "fell back"},
            {}};
    for (const BenchRecord& r : select(rs, [](const BenchRecord& x) { return x.group == "stress"; }))
      t.rows.push_back({r.path, r.scene, r.effect + "-" + std::to_string(r.samples), r.method,
                        fixed(static_cast<double>(r.shadedPixels) / (static_cast<double>(r.width) * r.height), 3),
                        fixed(r.idealSpeedup, 2) + "x", fixed(r.measuredSpeedup, 2) + "x", sci(r.error.rms),
                        r.error.edgeBandPixels > 0 ? sci(r.error.edgeBandRms) : "—", r.fellBack ? "yes" : ""});
    if (!t.rows.empty()) out.push_back(t);
  }
  return out;
}

std::string header(const BenchResults& res) {
  std::ostringstream o;
  o << "Machine: " << res.options.machine << ". ";
  for (const auto& [path, device] : res.devices) o << "Path " << path << ": " << device << ". ";
  o << "Median of " << res.options.repeats << " repeats after a warm-up, every method and `full` alternating in one "
    << "run. Effect time = frame time minus the full-res G-buffer and the shaded image for viewing (stage 6: the same "
    << "pass for every method, as the G-buffer; SPEC §10); measured speedup = full's "
    << "effect time / the method's; ideal speedup = W·H / shaded pixels (SPEC §4, §9). Errors: SPEC §10, the effect "
    << "buffer against `full` with the same samples; the edge band is the pixels near a transition of the level map, "
    << "so a method with one level has none (—). `mrr` and `mrr-effect` run with the never-slower rule (SPEC §11); "
    << "their `+norule` variants without it.\n";
  return o.str();
}

}  // namespace

std::vector<PaperFigure> readPaperFigures(const std::string& path) {
  std::vector<PaperFigure> out;
  std::ifstream in(path);
  if (!in) return out;
  std::string line;
  bool headerSeen = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!headerSeen) {
      headerSeen = true;  // figure,effect,samples,width,height,speedup_pct,rms
      continue;
    }
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) f.push_back(cell);
    while (f.size() < 7) f.emplace_back();
    try {
      PaperFigure p;
      p.figure = f[0];
      p.effect = f[1];
      p.samples = std::stoi(f[2]);
      p.width = std::stoi(f[3]);
      p.height = std::stoi(f[4]);
      if (!f[5].empty()) p.speedup = 1.0 + std::stod(f[5]) / 100.0;
      if (!f[6].empty()) p.rms = std::stod(f[6]);
      out.push_back(p);
    } catch (const std::exception&) {
      throw MrrError("paper figures " + path + ": cannot read the line '" + line + "'");
    }
  }
  return out;
}

constexpr double kMinTimedMs = 10.0;
constexpr double kJitterMs = 2.0;  // a frame's timing jitter on a loaded 2-core machine

std::vector<std::string> sanityChecks(const BenchResults& res) {
  std::vector<std::string> fails;
  for (const BenchRecord& r : res.records) {
    const std::string where = r.path + " " + r.scene + " camera " + std::to_string(r.camera) + " " +
                              sizeName(r.width, r.height) + " " + r.effect + "-" + std::to_string(r.samples) + " " + r.method;
    const double pixels = static_cast<double>(r.width) * r.height;
    if (r.method == referenceMethod()) {
      if (r.error.rms != 0.0 || r.error.maxAbs != 0.0 || r.flip != 0.0 || r.shadedFlip != 0.0)
        fails.push_back(where + ": full differs from its own warm-up frame (RMS " + sci(r.error.rms) + ", FLIP " +
                        sci(r.flip) + ")");
      if (static_cast<double>(r.shadedPixels) != pixels || r.idealSpeedup != 1.0)
        fails.push_back(where + ": full shades " + std::to_string(r.shadedPixels) + " pixels, not W·H");
      continue;
    }
    if (!std::isfinite(r.error.rms) || !std::isfinite(r.error.ssim) || r.error.ssim > 1.0 + 1e-9 ||
        !(r.flip >= 0.0 && r.flip <= 1.0) || !(r.shadedFlip >= 0.0 && r.shadedFlip <= 1.0))
      fails.push_back(where + ": error figures not finite, SSIM above 1 or FLIP outside [0,1]");
    // Timing noise: the method's time may fall short of what the ideal allows (full's time /
    // ideal) by 25% and, on top, by kJitterMs before it is called wrong, and only where full's
    // effect takes long enough (10 ms) for one timing to mean something. (CI measured a bumpy
    // 160×90 SSAO frame that fell back to full at 1.35× of full on llvmpipe: ~3 ms of jitter on
    // ~13.) Not where the method shades more pixels than full (ideal < 1: a stress scene where
    // every pixel is an edge): its extra pixels are coarse ones, cheaper than full-res ones, and
    // the pixel ratio bounds nothing there (CI measured SSM-196 mrr-norule on `alledges` at
    // 0.96× against 0.72×). Nor where the frame fell back to full (SPEC §11): it shades exactly
    // full's pixels, which the check below proves bit for bit, so its time against full's
    // measures timing noise alone (CI saw a fallen-back 160×90 SSGI frame on llvmpipe at 1.40×
    // of full while other tests ran).
    const double methodMs = r.fullEffectMs / std::max(r.measuredSpeedup, 1e-9);
    const double shortestMs = r.fullEffectMs / (1.25 * r.idealSpeedup + 0.05) - kJitterMs;
    if (r.fullEffectMs >= kMinTimedMs && r.idealSpeedup >= 1.0 && !r.fellBack && methodMs < shortestMs)
      fails.push_back(where + ": measured speedup " + fixed(r.measuredSpeedup, 2) + "x above the ideal " +
                      fixed(r.idealSpeedup, 2) + "x");
    if (r.fellBack && r.error.rms != 0.0) fails.push_back(where + ": fell back to full, yet differs from full");
  }
  for (const std::string& f : foveaSanityChecks(res.fovea)) fails.push_back(f);
  for (const StabilityRecord& s : res.stability)
    if (!std::isfinite(s.flicker) || s.flicker < 0.0 || !(s.flipFlicker >= 0.0 && s.flipFlicker <= 1.0) ||
        !(s.meanFlip >= 0.0 && s.meanFlip <= 1.0))
      fails.push_back(s.scene + " " + s.kind + " " + s.method + ": flicker not finite (or FLIP outside [0,1])");
  return fails;
}

namespace {
// --gpu-timing passes: each run's costliest programs, stage by stage (BenchRecord::passMs).
std::string passesMarkdown(const BenchResults& res) {
  std::ostringstream o;
  bool any = false;
  for (const BenchRecord& r : res.records) {
    if (r.passMs.empty()) continue;
    if (!any)
      o << "### Passes (--gpu-timing passes)\n\nEach draw timed alone, glFinish around it, medians of the repeats; "
           "read a pass as a share of its stage (docs/port.md, \"Where a frame's time goes, pass by pass\"). The "
           "ten costliest of each run:\n\n";
    any = true;
    std::vector<std::pair<std::string, double>> passes(r.passMs.begin(), r.passMs.end());
    std::sort(passes.begin(), passes.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
    o << "**" << r.path << " " << r.scene << " camera " << r.camera << " " << sizeName(r.width, r.height) << " "
      << r.effect << "-" << r.samples << " " << r.method << "**\n\n| stage (ms) | pass | ms |\n|---|---|---|\n";
    for (size_t i = 0; i < passes.size() && i < 10; ++i) {
      const std::string& key = passes[i].first;
      const size_t space = key.find(' ');
      const std::string stage = key.substr(0, space), pass = space == std::string::npos ? "" : key.substr(space + 1);
      const auto st = r.stageMs.find(stage);
      o << "| " << stage << " (" << fixed(st == r.stageMs.end() ? 0.0 : st->second, 2) << ") | `" << pass << "` | "
        << fixed(passes[i].second, 2) << " |\n";
    }
    o << "\n";
  }
  return o.str();
}
}  // namespace

std::string benchMarkdown(const BenchResults& res, const std::vector<std::string>& failures) {
  const std::vector<PaperFigure> paper = readPaperFigures(paperFiguresPath());
  std::ostringstream o;
  o << header(res) << "\n";
  if (paper.empty()) o << "(The paper's figures were not found at " << paperFiguresPath() << "; set MRR_PAPER_FIGURES.)\n\n";
  for (const Table& t : tables(res, paper)) o << t.markdown();
  o << foveaMarkdown(res.fovea);
  o << passesMarkdown(res);
  o << "### Sanity checks\n\n";
  if (failures.empty()) o << "All passed: full's error is 0 and it shades W·H pixels; no method beats its ideal speedup (where that is above 1); every figure is finite.\n";
  for (const std::string& f : failures) o << "- FAILED: " << f << "\n";
  return o.str();
}

nlohmann::json benchJson(const BenchResults& res, const std::vector<std::string>& failures) {
  nlohmann::json runs = nlohmann::json::array(), stab = nlohmann::json::array();
  for (const BenchRecord& r : res.records) {
    runs.push_back({{"path", r.path}, {"scene", r.scene}, {"group", r.group}, {"camera", r.camera}, {"method", r.method},
                    {"effect", r.effect}, {"width", r.width}, {"height", r.height}, {"samples", r.samples},
                    {"stage_ms", r.stageMs}, {"effect_ms", r.effectMs}, {"total_ms", r.totalMs},
                    {"shaded_pixels", r.shadedPixels}, {"ideal_speedup", r.idealSpeedup},
                    {"ideal_speedup_hit", r.idealSpeedupHit},
                    {"measured_speedup", r.measuredSpeedup}, {"fell_back_to_full", r.fellBack},
                    {"cold_effect_ms", r.coldEffectMs}, {"cold_speedup", r.coldSpeedup}, {"cold_process_ms", r.coldProcessMs},
                    {"rms", r.error.rms}, {"psnr", std::isfinite(r.error.psnr) ? nlohmann::json(r.error.psnr) : nlohmann::json(nullptr)},
                    {"ssim", r.error.ssim}, {"max_abs", r.error.maxAbs}, {"edge_band_rms", r.error.edgeBandRms},
                    {"shaded_rms", r.shadedRms}, {"flip", r.flip}, {"shaded_flip", r.shadedFlip}});
    if (!r.passMs.empty()) runs.back()["pass_ms"] = r.passMs;  // --gpu-timing passes
    if (std::isfinite(r.expectationRms)) {  // --expectation
      runs.back()["rms_expectation"] = r.expectationRms;
      runs.back()["mae_expectation"] = r.expectationMae;
    }
  }
  for (const StabilityRecord& s : res.stability) {
    stab.push_back({{"path", s.path}, {"scene", s.scene}, {"effect", s.effect}, {"samples", s.samples}, {"camera_path", s.kind},
                    {"frames", s.frames}, {"width", s.width}, {"height", s.height}, {"method", s.method},
                    {"flicker", s.flicker}, {"mean_rms", s.meanRms}, {"flip_flicker", s.flipFlicker},
                    {"mean_flip", s.meanFlip}});
    if (std::isfinite(s.expectationFlicker)) {  // --expectation
      stab.back()["expectation_flicker"] = s.expectationFlicker;
      stab.back()["expectation_mean_rms"] = s.expectationMeanRms;
    }
  }
  // The method table's rows, as the charts draw them (compare/report/report.py reads them here).
  const nlohmann::json methodRows = methodRowsJson();
  return {{"machine", res.options.machine}, {"devices", res.devices}, {"threads", res.threads},
          {"repeats", res.options.repeats}, {"methods", methodRows}, {"runs", runs}, {"stability", stab},
          {"fovea", foveaJson(res.fovea)}, {"sanity_failures", failures}};
}

namespace {
// A CSV cell: the figure, or empty where it was not measured (NaN).
std::string measured(double v) {
  if (!std::isfinite(v)) return "";
  std::ostringstream o;
  o << v;
  return o.str();
}
}  // namespace

std::string benchCsv(const BenchResults& res) {
  std::ostringstream o;
  o << "path,scene,group,camera,method,effect,width,height,samples,effect_ms,total_ms,shaded_pixels,ideal_speedup,"
       "ideal_speedup_hit,measured_speedup,fell_back,rms,psnr,ssim,max_abs,edge_band_rms,shaded_rms,cold_effect_ms,"
       "cold_speedup,flip,shaded_flip,cold_process_ms,rms_expectation,mae_expectation\n";
  for (const BenchRecord& r : res.records)
    o << r.path << "," << r.scene << "," << r.group << "," << r.camera << "," << r.method << "," << r.effect << "," << r.width
      << "," << r.height << "," << r.samples << "," << r.effectMs << "," << r.totalMs << "," << r.shadedPixels << ","
      << r.idealSpeedup << "," << r.idealSpeedupHit << "," << r.measuredSpeedup << "," << (r.fellBack ? 1 : 0) << "," << r.error.rms << ","
      << (std::isfinite(r.error.psnr) ? std::to_string(r.error.psnr) : "inf") << "," << r.error.ssim << "," << r.error.maxAbs
      << "," << r.error.edgeBandRms << "," << r.shadedRms << "," << r.coldEffectMs << "," << r.coldSpeedup << "," << r.flip << ","
      << r.shadedFlip << "," << r.coldProcessMs << "," << measured(r.expectationRms) << "," << measured(r.expectationMae)
      << "\n";
  return o.str();
}

std::string benchStabilityCsv(const BenchResults& res) {
  std::ostringstream o;
  o << "path,scene,effect,samples,camera_path,frames,width,height,method,flicker,mean_rms,flip_flicker,mean_flip,"
       "expectation_flicker,expectation_mean_rms\n";
  for (const StabilityRecord& s : res.stability)
    o << s.path << "," << s.scene << "," << s.effect << "," << s.samples << "," << s.kind << "," << s.frames << "," << s.width
      << "," << s.height << "," << s.method << "," << s.flicker << "," << s.meanRms << "," << s.flipFlicker << ","
      << s.meanFlip << "," << measured(s.expectationFlicker) << "," << measured(s.expectationMeanRms) << "\n";
  return o.str();
}

std::string stabilityCsvPath(const std::string& csvPath) {
  const std::filesystem::path p(csvPath);
  return (p.parent_path() / (p.stem().string() + "-stability.csv")).string();
}

void writeBenchReport(const std::string& dir, const BenchResults& res, const std::vector<std::string>& failures) {
  const std::vector<PaperFigure> paper = readPaperFigures(paperFiguresPath());
  nlohmann::json paperData = nlohmann::json::array(), tableData = nlohmann::json::array();
  for (const PaperFigure& p : paper)
    paperData.push_back({{"figure", p.figure}, {"effect", p.effect}, {"samples", p.samples}, {"width", p.width},
                         {"height", p.height}, {"speedup", p.speedup}, {"rms", p.rms}});
  for (const Table& t : tables(res, paper)) tableData.push_back({{"title", t.title}, {"header", t.header}, {"rows", t.rows}});
  // report.py draws the charts from the runs into DIR/charts and lists DIR/images (the sweep's
  // example images); the page names both relative to DIR.
  const ReportJob job;
  const std::string page = job.makePage({{"kind", "bench"},
                                         {"out_dir", std::filesystem::absolute(dir).string()},
                                         {"header", header(res)},
                                         {"paper", paperData},
                                         {"paper_path", paperFiguresPath()},
                                         {"failures", failures},
                                         {"tables", tableData},
                                         {"results", benchJson(res, failures)}});
  writeTextFile(dir + "/index.html", page);
}

}  // namespace mrr
