#include "compare/rule/rule.h"

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <ostream>
#include <thread>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/image_io.h"
#include "common/stages.h"
#include "scenes/default_light.h"

namespace mrr {

namespace {
// The method the rule decides for (common/methods.h: the paper's), and it without the rule; a
// decision is this name, or full's ("full", and "full-early", "full-floor" for the early ones).
std::string paperMethod() { return toString(Mode::Mrr); }
std::string withoutRule() { return paperMethod() + "+norule"; }
}  // namespace

namespace {

constexpr double kPi = 3.14159265358979323846;
// The fits price in ns (per pixel, per sample), the stages are timed in ms.
constexpr double kNsPerMs = 1e6;
double msToNs(double ms) { return ms * kNsPerMs; }
// The sweep's verdict: a mode is the faster when its median frame is within 5% of the other's,
// and a pair of runs is past the bar the wrong way when its ratio is beyond it (judge).
constexpr double kFasterWithin = 1.05;
// A frame whose medians put the method within ±10% of full (mrr/full in this band) gets as many
// rounds again: its verdict is the one noise sways.
constexpr double kNearBreakEvenLow = 0.9, kNearBreakEvenHigh = 1.1;
// ruleViews: the sky looks 50° above the horizon; the close-up is a quarter of the way from the
// target to the eye.
constexpr double kSkyElevationDegrees = 50.0;
constexpr float kCloseUpDistance = 0.25f;

// A stage's median by its row in the stage list (0 where the frame did not run it: SSAO draws no
// shadow map, full no edges).
double timedMs(const std::map<std::string, double>& ms, Timed t, int level = -1) {
  const auto it = ms.find(timedName(t, level));
  return it != ms.end() ? it->second : 0.0;
}
// The effect's shading stages (per shaded pixel: a, b, c, s) and its per-level-pixel ones (d).
double shadingMs(const std::map<std::string, double>& ms) { return costClassMs(ms, CostClass::Shading); }
double levelPixelMs(const std::map<std::string, double>& ms) { return costClassMs(ms, CostClass::LevelPixel); }
// What SPEC §11 predicts: the frame after its decision point (the full-res G-buffer, the shadow
// map and test, the edges and masks, and the shaded image for viewing are paid before or by both).
double restMs(const std::map<std::string, double>& ms) {
  double paid = 0.0;
  for (CostClass c : {CostClass::Shared, CostClass::Detection, CostClass::Viewing}) paid += costClassMs(ms, c);
  return timedMs(ms, Timed::Total) - paid;
}
// The frame less what every mode pays alike, before the rule decides anything: the full-res
// G-buffer, and for SSM and SSGI the shadow map and its one-tap test (the same work on the same
// inputs in both modes; SSM's 2048² map is 30 ms of a 40 ms small frame, and its run-to-run
// noise would decide which mode looks faster).
double frameMs(const std::map<std::string, double>& ms) {
  return timedMs(ms, Timed::Total) - costClassMs(ms, CostClass::Shared);
}
// The p-quantile of v by nearest rank (p in [0, 1]; 0 for none).
double quantile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(std::lround(p * static_cast<double>(v.size() - 1)))];
}

struct Measured {
  std::map<std::string, double> ms;  // medians per stage
  FrameResult last;
};

// Renders `constants` once to warm up, then `repeats` times; medians per stage. `model`: the
// cost model the frame's rule counts with (default: the path's built-in).
Measured measure(const RenderFn& render, const Camera& camera, const Constants& constants, int repeats,
                 const CostModel* model = nullptr) {
  std::map<std::string, std::vector<double>> runs;
  Measured m;
  for (int i = 0; i <= repeats; ++i) {
    FrameResult f = render(camera, constants, {false, {}, model, true});
    if (i == 0) continue;
    for (const auto& [k, v] : stageMs(f)) runs[k].push_back(v);
    if (i == repeats) m.last = std::move(f);
  }
  for (const auto& [k, v] : runs) m.ms[k] = median(v);
  return m;
}

// Least squares with non-negative coefficients (a handful of unknowns): the normal equations
// solved on the columns still free, a negative coefficient fixed at 0 and the rest refitted.
struct LeastSquares {
  std::vector<std::vector<double>> rows;
  std::vector<double> y;
  void add(std::vector<double> row, double value) {
    rows.push_back(std::move(row));
    y.push_back(value);
  }
  // A row weighted by 1/measured: the fit minimises relative errors, so the small frames, where
  // the per-frame costs decide, count as much as the large ones (the rule compares two
  // predictions of one frame: their relative error decides it).
  void addRelative(std::vector<double> row, double value, double measured) {
    const double w = 1.0 / std::max(std::abs(measured), 1e-9);
    for (double& v : row) v *= w;
    add(std::move(row), value * w);
  }
  std::vector<double> solve() const {
    const size_t unknowns = rows.empty() ? 0 : rows.front().size();
    std::vector<bool> free(unknowns, true);
    std::vector<double> x(unknowns, 0.0);
    for (size_t round = 0; round <= unknowns; ++round) {
      std::vector<size_t> cols;
      for (size_t i = 0; i < unknowns; ++i)
        if (free[i]) cols.push_back(i);
      const size_t n = cols.size();
      std::fill(x.begin(), x.end(), 0.0);
      if (n == 0) return x;
      std::vector<std::vector<double>> a(n, std::vector<double>(n + 1, 0.0));
      for (size_t r = 0; r < rows.size(); ++r)
        for (size_t i = 0; i < n; ++i) {
          for (size_t j = 0; j < n; ++j) a[i][j] += rows[r][cols[i]] * rows[r][cols[j]];
          a[i][n] += rows[r][cols[i]] * y[r];
        }
      for (size_t i = 0; i < n; ++i) {  // Gauss-Jordan with partial pivoting
        size_t pivot = i;
        for (size_t k = i + 1; k < n; ++k)
          if (std::abs(a[k][i]) > std::abs(a[pivot][i])) pivot = k;
        std::swap(a[i], a[pivot]);
        if (std::abs(a[i][i]) < 1e-300) continue;
        for (size_t k = 0; k < n; ++k) {
          if (k == i) continue;
          const double f = a[k][i] / a[i][i];
          for (size_t j = i; j <= n; ++j) a[k][j] -= f * a[i][j];
        }
      }
      bool negative = false;
      for (size_t i = 0; i < n; ++i) {
        const double v = std::abs(a[i][i]) < 1e-300 ? 0.0 : a[i][n] / a[i][i];
        x[cols[i]] = v;
        if (v < 0.0) {
          free[cols[i]] = false;
          negative = true;
        }
      }
      if (!negative) return x;
    }
    for (double& v : x) v = std::max(v, 0.0);
    return x;
  }
};

}  // namespace

double costClassMs(const std::map<std::string, double>& ms, CostClass cost) {
  double sum = 0.0;
  for (const auto& [name, v] : ms)
    if (parseTimed(name).cost() == cost) sum += v;
  return sum;
}

std::vector<RuleView> ruleViews(const Scene& scene, const Camera& catalogue, float aspect) {
  std::vector<RuleView> views;
  views.push_back({"catalogue", catalogue});
  views.push_back({"default", frameScene(scene, catalogue.yfov, aspect).camera});
  const glm::vec3 up = glm::normalize(catalogue.up);
  const glm::vec3 forward = glm::normalize(catalogue.target - catalogue.eye);
  glm::vec3 level = forward - glm::dot(forward, up) * up;
  level = glm::length(level) > 1e-4f ? glm::normalize(level) : glm::vec3(std::abs(up.x) < 0.9f ? 1 : 0, 0, std::abs(up.x) < 0.9f ? 0 : 1);
  const float elevation = static_cast<float>(kSkyElevationDegrees * kPi / 180.0);
  Camera sky = catalogue;
  sky.target = catalogue.eye + (level * std::cos(elevation) + up * std::sin(elevation)) * glm::length(catalogue.target - catalogue.eye);
  views.push_back({"sky", sky});
  Camera close = catalogue;
  close.eye = catalogue.target + (catalogue.eye - catalogue.target) * kCloseUpDistance;
  views.push_back({"close-up", close});
  return views;
}

void fitSparseFactorAndFixedCost(CostModel& model, Effect e, const std::vector<CalibrationFrame>& frames) {
  // The method's rest of frame = Σ_ℓ (q_ℓ + s (1 − q_ℓ)) × (its level-ℓ shading on geometry,
  // priced as full's) + k + the rest as priced by the model's other figures: affine in s (with
  // s = 0 the prediction holds the q_ℓ part, with s = 1 the whole shading), least squares over
  // every size and both sample counts. The small frames tell the per-frame k (pass set-up) from
  // the per-pixel s (a stencilled pixel's premium).
  EffectCost& ec = model.effect[static_cast<size_t>(e)];
  LeastSquares fit;
  std::vector<std::pair<double, double>> xy;  // (shading on geometry, the rest less the others), ms
  for (const CalibrationFrame& r : frames) {
    if (r.effect != e) continue;
    CostModel m = model;
    m.effect[static_cast<size_t>(e)].fixedMs = 0.0;
    m.effect[static_cast<size_t>(e)].sparseFactor = 0.0;
    const double others = predictMrrMs(m, r.constants, r.counts);
    m.effect[static_cast<size_t>(e)].sparseFactor = 1.0;
    const double shading = predictMrrMs(m, r.constants, r.counts) - others;
    fit.addRelative({shading, 1.0}, r.restMs - others, r.restMs);
    xy.emplace_back(shading, r.restMs - others);
  }
  const std::vector<double> sk = fit.solve();
  ec.sparseFactor = sk.empty() ? 1.0 : sk[0];
  ec.fixedMs = sk.size() > 1 ? sk[1] : 0.0;
  // A stencilled pixel costs no less than a dense one, and the dearest no more than twice the
  // dense mean (SPEC §11: those a stencil takes last then cost 2 − s of it): outside, s at the
  // bound and k alone.
  if (ec.sparseFactor < kMinSparseFactor || ec.sparseFactor > kMaxSparseFactor) {
    ec.sparseFactor = std::clamp(ec.sparseFactor, kMinSparseFactor, kMaxSparseFactor);
    double residual = 0.0;
    for (const auto& [x, y] : xy) residual += y - ec.sparseFactor * x;
    ec.fixedMs = xy.empty() ? 0.0 : std::max(0.0, residual / static_cast<double>(xy.size()));
  }
}

void fitStencilFill(CostModel& model, const std::vector<CalibrationFrame>& frames) {
  // Per level below the coarsest, (φ_ℓ, η_ℓ) minimising Σ (|Ŝ_ℓ| / |S_ℓ| − 1)² over the frames
  // whose level ℓ is shaded and reached: a grid, φ in steps of 1/200 on [0, 1] and η on a log scale
  // from 1/16 to 64 (a fit in closed form would have to split the frames at min's corner). Relative,
  // as every fit here: the rule's error is relative.
  constexpr int kFillSteps = 200, kBandSteps = 480;
  constexpr double kBandLo = 1.0 / 16.0, kBandHi = 64.0;
  for (size_t l = 0; l < model.stencilFill.size(); ++l) {
    std::vector<const CalibrationFrame*> use;
    for (const CalibrationFrame& f : frames) {
      const LevelConstants& lc = f.constants.levels[l];
      if (lc.enabled && lc.shaded && lc.index < f.constants.coarsestEnabled && f.counts.reach[l] > 0 && f.counts.shaded[l] > 0)
        use.push_back(&f);
    }
    if (use.empty()) continue;  // the level unseen: the model keeps what it had
    double best = std::numeric_limits<double>::infinity();
    for (int bi = 0; bi <= kBandSteps; ++bi) {
      const double band = kBandLo * std::pow(kBandHi / kBandLo, static_cast<double>(bi) / kBandSteps);
      for (int fi = 0; fi <= kFillSteps; ++fi) {
        const double fill = static_cast<double>(fi) / kFillSteps;
        double squares = 0.0;
        for (const CalibrationFrame* f : use) {
          const double off = estimateStencilPixels(fill, band, f->constants.levels[l], f->counts) /
                                 static_cast<double>(f->counts.shaded[l]) -
                             1.0;
          squares += off * off;
        }
        if (squares < best) {
          best = squares;
          model.stencilFill[l] = fill;
          model.edgeBandFill[l] = band;
        }
      }
    }
  }
}

namespace {

// The calibration's frames: the method and full at the middle size, at half and at twice it
// (320×180 to 1280×720: the sizes tell the per-frame costs from the per-pixel ones), from three
// views (the default framing is left out: three are enough to separate H from W·H − H).
constexpr int kCalibrationWidth = 640, kCalibrationHeight = 360;
// Per effect, a low and a high sample count: where a pixel's fixed part (a; SSM's blocker search)
// is most of its cost, and where the samples are.
int fewSamples(Effect e) { return e == Effect::Ssm ? 16 : 8; }
int manySamples(Effect e) { return e == Effect::Ssm ? 256 : 128; }
// A full frame with less than this share of its pixels on geometry is "the sky": c and k₀ are
// fitted on those alone, where nothing else is paid.
constexpr double kSkyShare = 0.05;

// A full frame's shading against what it shades: H_a, H_a·N (, H_p·N, Σ f over H_a), W·H, W·H − H_a.
struct FullRun {
  std::vector<double> onGeometry;  // H_a, H_a·N (, H_p·N, Σ f over H_a)
  double pixels, background, ns;   // W·H, W·H − H_a, the shading's time
};

// What the calibration measured, as rows of its fits (SPEC §11's figures in brackets).
struct CalibrationRuns {
  std::array<std::vector<FullRun>, 3> fullRuns;  // per effect: a, b (, e, ν), c and k₀
  // Per-pixel slopes from affine fits over the three sizes (P, 1): the intercepts are the passes'
  // set-up, paid per frame whatever its size; full's go to k₀, the method's to k (fitted on the
  // rest, which holds them).
  std::array<LeastSquares, 3> levelFit;  // per effect, full frames: P_0 (H / W·H), 1 → d (SSAO's planes, SSGI's direct light)
  std::array<LeastSquares, 3> ruleFit;   // per effect, the method's frames: W·H, 1 → ρ (the rule's own counts)
  LeastSquares fullBlendFit, blendFit;   // full's blend: W·H, 1 → β₀; the method's: W·H, |S_j| s_j², 1 → β₀ + β, β_f
  LeastSquares gbufferFit;               // P_ℓ, 1 → g (the pass's set-up goes to k)
  LeastSquares edgesFit, masksFit;       // P_0, H, 1 → ε, ε_h, κ's share; P_0, A, 1 → μ, μ_A, the rest of κ
  // mrr-effect's masks less mrr's on the same view and size: P_0 → μ_e; its a-posteriori variant's
  // less the a-priori one's: Σ_{ℓ refined} P_ℓ → μ_v (SPEC §11; no intercept: both pay κ alike)
  LeastSquares effectMaskFit, refineFit;
  std::vector<CalibrationFrame> mrrRuns;  // every size and both counts: s (per pixel) from k (per frame)
};

// The one way a stage's time becomes a row of a fit: ns = Σ figure × count + a per-frame part (the
// last column, kNsPerMs, so that its figure reads in ms), relative (weighted by 1/measured: the
// rule's error is relative). A stage the frame did not run (0 ms) adds nothing.
void addStageTime(LeastSquares& fit, std::vector<double> counts, double ms) {
  const double ns = msToNs(ms);
  if (ns <= 0.0) return;
  counts.push_back(kNsPerMs);
  fit.addRelative(std::move(counts), ns, ns);
}
// A fit's i-th figure, `otherwise` where the fit had nothing to go on.
double figure(const std::vector<double>& solved, size_t i, double otherwise = 0.0) {
  return i < solved.size() ? solved[i] : otherwise;
}

// Full at both sample counts at the middle size, and at the high count at half and twice it: the
// shading against what it shades, the per-level-pixel stages and the blend.
void measureFull(CalibrationRuns& runs, const OpenScene& sc, const Camera& camera, float framed, Effect e,
                 int repeats, const std::array<const FrameCounts*, 3>& countsBySize) {
  const auto ei = static_cast<size_t>(e);
  struct FullConfig {
    int width, height, samples;
    const FrameCounts* counts;  // the method's at the same size: H_a, H_p, Σ f
  };
  const int w = kCalibrationWidth, h = kCalibrationHeight;
  for (const FullConfig& fc : {FullConfig{w, h, fewSamples(e), countsBySize[1]}, FullConfig{w, h, manySamples(e), countsBySize[1]},
                               FullConfig{w / 2, h / 2, manySamples(e), countsBySize[0]},
                               FullConfig{2 * w, 2 * h, manySamples(e), countsBySize[2]}}) {
    const Measured full = measure(
        sc.render, camera, makeConstants(settingsFor(referenceMethod(), e, fc.width, fc.height, fc.samples), framed), repeats);
    const double p = static_cast<double>(fc.width) * fc.height, onGeometry = static_cast<double>(fc.counts->searchedPixels);
    std::vector<double> row = {onGeometry, onGeometry * fc.samples};
    if (e == Effect::Ssm) {
      row.push_back(static_cast<double>(fc.counts->pcfPixels) * fc.samples);
      row.push_back(static_cast<double>(fc.counts->searchedFootprint) / kFootprintSteps);  // Σ f over H_a
    }
    runs.fullRuns[ei].push_back({row, p, p - onGeometry, msToNs(shadingMs(full.ms))});
    const double hits = static_cast<double>(fc.counts->hitPixels);  // P_0 (H / W·H) = H
    addStageTime(runs.levelFit[ei], {hits}, levelPixelMs(full.ms));
    addStageTime(runs.fullBlendFit, {p}, timedMs(full.ms, Timed::Blend));
  }
}

// The method's stages beside its effect, at one size: the coarse G-buffers, the rule, the blend,
// the edges and the masks.
void addMethodStages(CalibrationRuns& runs, Effect e, const Measured& m) {
  const Constants& mc = m.last.constants;
  const FrameCounts& mn = m.last.counts;
  const double frame = static_cast<double>(mc.width) * mc.height;
  for (const LevelConstants& lc : mc.levels)
    if (lc.enabled && lc.index > 0)
      addStageTime(runs.gbufferFit, {static_cast<double>(lc.width) * lc.height}, timedMs(m.ms, Timed::GBuffer, lc.index));
  addStageTime(runs.ruleFit[static_cast<size_t>(e)], {frame}, timedMs(m.ms, Timed::Rule));
  addStageTime(runs.blendFit, {frame, finerLevelsArea(mc, mn.shaded)}, timedMs(m.ms, Timed::Blend));
  const double padded = static_cast<double>(mc.levels[0].width) * mc.levels[0].height;
  double reach = 0.0;
  for (int64_t r : mn.reach) reach += static_cast<double>(r);
  addStageTime(runs.edgesFit, {padded, static_cast<double>(mn.hitPixels)}, timedMs(m.ms, Timed::Edges));
  addStageTime(runs.masksFit, {padded, reach}, timedMs(m.ms, Timed::Masking));
}

// The τ_v the calibration's a-posteriori frames refine with (the bench's +p0.3).
constexpr float kCalibrationPosterior = 0.3f;

// mrr-effect (rule off) at one size beside the method's frame `mrr` there: its masks' time less
// mrr's, per padded pixel (μ_e); with `posterior` (the oracle), its a-posteriori variant's less
// the a-priori one's, per refined level pixel (μ_v). A difference the machine's noise made ≤ 0 adds
// no row.
void measureEffectMasks(CalibrationRuns& runs, const OpenScene& sc, const Camera& camera, float framed, Effect e,
                        int repeats, const CostModel& counting, const Measured& mrr, bool posterior) {
  const Constants& mc = mrr.last.constants;
  Settings s = settingsFor(toString(Mode::MrrEffect), e, mc.width, mc.height, mc.samples());
  s.neverSlower = false;
  const Measured effect = measure(sc.render, camera, makeConstants(s, framed), repeats, &counting);
  const double padded = static_cast<double>(mc.levels[0].width) * mc.levels[0].height;
  const double extra = msToNs(timedMs(effect.ms, Timed::Masking) - timedMs(mrr.ms, Timed::Masking));
  if (extra > 0.0) runs.effectMaskFit.addRelative({padded}, extra, extra);
  if (!posterior) return;
  s.effectMask.posterior = kCalibrationPosterior;
  const Constants pc = makeConstants(s, framed);
  CostModel unit;  // refineNs with μ_v = 1: the refined levels' pixels
  unit.nsPerRefinePixel = 1.0;
  const Measured refined = measure(sc.render, camera, pc, repeats, &counting);
  const double refine = msToNs(timedMs(refined.ms, Timed::Masking) - timedMs(effect.ms, Timed::Masking));
  if (refine > 0.0) runs.refineFit.addRelative({refineNs(unit, pc)}, refine, refine);
}

// One scene, view and effect: the method (rule off) at the three sizes and the low count, full
// at both counts (measureFull), mrr-effect at the middle size (measureEffectMasks), into the
// fits' rows.
void measureView(CalibrationRuns& runs, const OpenScene& sc, const Camera& camera, Effect e, int repeats,
                 const CostModel& counting, bool posterior) {
  const int w = kCalibrationWidth, h = kCalibrationHeight;
  const float framed = framedSize(*sc.scene, camera, static_cast<float>(w) / static_cast<float>(h)).size;
  auto method = [&](int width, int height, int samples) {
    return measure(sc.render, camera, makeConstants(settingsFor(withoutRule(), e, width, height, samples), framed),
                   repeats, &counting);
  };
  const Measured mrr = method(w, h, manySamples(e));
  const Measured small = method(w / 2, h / 2, manySamples(e));
  const Measured large = method(2 * w, 2 * h, manySamples(e));
  measureFull(runs, sc, camera, framed, e, repeats, {&small.last.counts, &mrr.last.counts, &large.last.counts});
  // and at the low sample count: where a pixel's fixed part (a; SSM's blocker search) is most
  // of its cost, the stencilled pixel's premium differs from the one at the high count (PCF's taps)
  const Measured few = method(w, h, fewSamples(e));
  for (const Measured* m : {&mrr, &small, &large, &few})
    runs.mrrRuns.push_back({e, m->last.constants, m->last.counts, restMs(m->ms)});
  for (const Measured* m : {&small, &mrr, &large}) addMethodStages(runs, e, *m);
  measureEffectMasks(runs, sc, camera, framed, e, repeats, counting, mrr, posterior);
}

// c and k₀ from the frames nearly all sky (at every size), then a, b (, e, ν) on the rest with
// those fixed; ρ and d from their stages (d's intercept is full's one level pass, in k₀).
void fitEffect(CostModel& model, Effect e, const CalibrationRuns& runs) {
  const auto ei = static_cast<size_t>(e);
  EffectCost& ec = model.effect[ei];
  LeastSquares sky;
  for (const FullRun& r : runs.fullRuns[ei])
    if (r.onGeometry[0] < kSkyShare * r.pixels) sky.addRelative({r.background, kNsPerMs}, r.ns, r.ns);
  const std::vector<double> ck = sky.solve();
  ec.nsPerBackgroundPixel = figure(ck, 0);
  ec.fullFixedMs = figure(ck, 1);
  LeastSquares fit;
  for (const FullRun& r : runs.fullRuns[ei])
    if (r.onGeometry[0] >= kSkyShare * r.pixels)
      fit.addRelative(r.onGeometry, r.ns - r.background * ec.nsPerBackgroundPixel - msToNs(ec.fullFixedMs), r.ns);
  const std::vector<double> ab = fit.solve();
  ec.nsPerShadedPixel = figure(ab, 0);
  ec.nsPerSample = figure(ab, 1);
  ec.nsPerPcfSample = figure(ab, 2);
  ec.nsPerFootprintTexel = figure(ab, 3);
  ec.nsPerRulePixel = figure(runs.ruleFit[ei].solve(), 0);  // its intercept stays in the rest, where k takes it
  const std::vector<double> d = runs.levelFit[ei].solve();
  ec.nsPerLevelPixel = figure(d, 0);
  ec.fullFixedMs += figure(d, 1);  // full's one level pass
}

// g, β₀ (full's blend: its level 0 copied into the result), β and β_f (the method's beyond it),
// ε, ε_h, μ, μ_A and κ (the edges and the masks per padded pixel and per frame), μ_e and μ_v
// (mrr-effect's masks and its a-posteriori refinement).
void fitSharedStages(CostModel& model, const CalibrationRuns& runs) {
  model.nsPerCoarseGbufferPixel = figure(runs.gbufferFit.solve(), 0);
  const std::vector<double> fullBlend = runs.fullBlendFit.solve(), blend = runs.blendFit.solve();
  model.nsPerFullBlendPixel = figure(fullBlend, 0);
  for (EffectCost& ec : model.effect) ec.fullFixedMs += figure(fullBlend, 1);
  model.nsPerBlendPixel = std::max(0.0, figure(blend, 0) - model.nsPerFullBlendPixel);
  model.nsPerFineBlendPixel = figure(blend, 1);
  const std::vector<double> edgeCost = runs.edgesFit.solve(), maskCost = runs.masksFit.solve();
  model.nsPerEdgePixel = figure(edgeCost, 0);
  model.nsPerEdgeHitPixel = figure(edgeCost, 1);
  model.nsPerMaskPixel = figure(maskCost, 0);
  model.nsPerMaskReachPixel = figure(maskCost, 1);
  model.edgesMasksFixedMs = figure(edgeCost, 2) + figure(maskCost, 2);
  model.nsPerEffectMaskPixel = figure(runs.effectMaskFit.solve(), 0);
  model.nsPerRefinePixel = figure(runs.refineFit.solve(), 0);
}

// w: the early estimate of the method's rest (from the edge sample) against the one its stencils
// give, relative, over every frame of the method: a uniform of that RMS spans ±√3 RMS.
double estimateSpread(const CostModel& model, const std::vector<CalibrationFrame>& frames) {
  double squares = 0.0;
  for (const CalibrationFrame& r : frames) {
    const double late = predictMrrMs(model, r.constants, r.counts);
    const double early = predictMrrMs(model, r.constants, estimateStencils(model, r.constants, r.counts));
    const double off = early / std::max(late, 1e-9) - 1.0;
    squares += off * off;
  }
  return frames.empty() ? 0.0 : std::sqrt(3.0 * squares / static_cast<double>(frames.size()));
}

}  // namespace

CostModel calibrateCostModel(const BenchPath& path, int repeats, int threads) {
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(std::max(threads, 1)));
  CostModel model;
  model.source = "mrr bench --calibrate, " + path.name + " (" + path.device + "), builtin:corner, builtin:demo and builtin:bumpy " +
                 std::to_string(kCalibrationWidth / 2) + "x" + std::to_string(kCalibrationHeight / 2) + " to " +
                 std::to_string(2 * kCalibrationWidth) + "x" + std::to_string(2 * kCalibrationHeight);
  // The method's frames count with a model that prices PCF (e > 0), so that SSM's frames sample
  // where PCF runs (H_p) on both paths, whatever the built-in model says: e is fitted from them.
  CostModel counting = CostModel::defaults(path.name);
  counting.effect[static_cast<size_t>(Effect::Ssm)].nsPerPcfSample = 1.0;
  CalibrationRuns runs;
  for (const char* sceneName : {"builtin:corner", "builtin:demo", "builtin:bumpy"}) {
    const OpenScene sc = openScene(sceneName, path);
    for (const RuleView& view :
         ruleViews(*sc.scene, sc.camera, static_cast<float>(kCalibrationWidth) / kCalibrationHeight)) {
      if (view.name == "default") continue;  // three views are enough to separate H from W·H − H
      for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
        std::cerr << "[calibrate] " << path.name << " " << sceneName << " " << view.name << " " << toString(e) << "\n";
        measureView(runs, sc, view.camera, e, repeats, counting, path.name == "cpu");
      }
    }
  }
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) fitEffect(model, e, runs);
  fitSharedStages(model, runs);
  // φ_ℓ and η_ℓ: how the stencils fill the edge sample's reach, over every frame and size (a level
  // no frame reaches keeps the built-in figures)
  model.stencilFill = counting.stencilFill;
  model.edgeBandFill = counting.edgeBandFill;
  fitStencilFill(model, runs.mrrRuns);
  // s and k, per effect, over the method's frames at every size and both sample counts
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) fitSparseFactorAndFixedCost(model, e, runs.mrrRuns);
  model.estimateSpread = estimateSpread(model, runs.mrrRuns);
  return model;
}

namespace {

struct Verdict {
  bool right = false, wrongBeyondNoise = false;
};

// The rule chose right when the mode it took is the faster within 5% (by the medians); wrong beyond
// the machine's noise when, besides, three quarters of the pairs are past the 5% bar the wrong way
// (on llvmpipe a frame all sky, where the method does strictly more work, has measured 1.18×
// faster than full by its medians).
Verdict judge(const std::string& decision, double fullMs, double mrrMs, const std::vector<double>& pairRatios) {
  const bool keptMrr = decision == paperMethod();
  Verdict v;
  v.right = keptMrr ? mrrMs <= kFasterWithin * fullMs : fullMs <= kFasterWithin * mrrMs;
  v.wrongBeyondNoise = !v.right && (keptMrr ? quantile(pairRatios, 0.25) > kFasterWithin
                                            : quantile(pairRatios, 0.75) * kFasterWithin < 1.0);
  return v;
}

// The summary: how often the rule chose the faster mode (within 5%), and the worst of each way.
// A frame without a with-rule time (rule_ms null: a replay whose model falls back where the sweep
// kept the method) is left out of the worst with-rule/full, and counted.
nlohmann::json summarize(const nlohmann::json& frames) {
  int right = 0, kept = 0, fell = 0, wrongBeyondNoise = 0, unmeasured = 0;
  double worstKept = 0.0, worstFell = 0.0, worstRule = 0.0;
  for (const nlohmann::json& f : frames) {
    right += f["right"].get<bool>();
    wrongBeyondNoise += f["wrong_beyond_noise"].get<bool>();
    const double fullMs = f["full_ms"], mrrMs = f["mrr_ms"];
    if (f["rule_ms"].is_number())
      worstRule = std::max(worstRule, f["rule_ms"].get<double>() / fullMs);
    else
      ++unmeasured;
    if (f["decision"] == paperMethod()) {
      ++kept;
      worstKept = std::max(worstKept, mrrMs / fullMs);
    } else {
      ++fell;
      worstFell = std::max(worstFell, fullMs / mrrMs);
    }
  }
  nlohmann::json summary = {{"frames", frames.size()},
                            {"right", right},
                            {"wrong_beyond_noise", wrongBeyondNoise},
                            {"kept_mrr", kept},
                            {"fell_back", fell},
                            {"worst_kept_mrr_over_full", worstKept},
                            {"worst_fell_back_full_over_mrr", worstFell},
                            {"worst_rule_over_full", worstRule}};
  if (unmeasured > 0) summary["rule_unmeasured"] = unmeasured;
  // How far the model's prices were from the times, relative (predicted / measured − 1), RMS and
  // median over the frames: full's rest, the method's rest on its stencils, and the early estimate
  // of the method from its edges on (edges, masks and R̂, against the rest and the edges and masks
  // measured). What to read before a decision: a model priced low or high on a machine.
  auto error = [&](auto predicted, auto measured) {
    std::vector<double> off;
    for (const nlohmann::json& f : frames)
      if (const double m = measured(f); m > 0.0) off.push_back(predicted(f) / m - 1.0);
    double squares = 0.0;
    for (double o : off) squares += o * o;
    return nlohmann::json{{"rms", off.empty() ? 0.0 : std::sqrt(squares / static_cast<double>(off.size()))},
                          {"median", median(off)}};
  };
  auto field = [](const char* key) { return [key](const nlohmann::json& f) { return f[key].get<double>(); }; };
  summary["prediction_error"] = {
      {"full_rest", error(field("predicted_full_rest_ms"), field("measured_full_rest_ms"))},
      {"mrr_rest", error(field("predicted_mrr_rest_ms"), field("measured_mrr_rest_ms"))},
      {"mrr_early_estimate", error(field("predicted_mrr_estimate_ms"), [](const nlohmann::json& f) {
         const auto stages = f["mrr_stages_ms"].get<std::map<std::string, double>>();
         return f["measured_mrr_rest_ms"].get<double>() + costClassMs(stages, CostClass::Detection);
       })}};
  return summary;
}

void printSummary(const nlohmann::json& s, std::ostream& out) {
  const size_t frames = s["frames"];
  const int right = s["right"];
  const std::string unmeasured =
      s.contains("rule_unmeasured") ? " (" + std::to_string(s["rule_unmeasured"].get<int>()) + " unmeasured)" : "";
  char line[512];
  std::snprintf(line, sizeof line,
                "| frames | right (faster within %.0f%%) | wrong beyond noise | kept mrr | fell back | worst mrr/full where kept | "
                "worst full/mrr where fallen back | worst with-rule/full |\n|---|---|---|---|---|---|---|---|\n| %zu | %d (%.1f%%) | "
                "%d | %d | %d | %.3f | %.3f | %.3f%s |\n",
                100.0 * (kFasterWithin - 1.0), frames, right, 100.0 * right / static_cast<double>(std::max<size_t>(frames, 1)),
                s["wrong_beyond_noise"].get<int>(), s["kept_mrr"].get<int>(), s["fell_back"].get<int>(),
                s["worst_kept_mrr_over_full"].get<double>(), s["worst_fell_back_full_over_mrr"].get<double>(),
                s["worst_rule_over_full"].get<double>(), unmeasured.c_str());
  out << line;
  if (const auto p = s.find("prediction_error"); p != s.end()) {
    const nlohmann::json& e = *p;
    auto both = [&](const char* key) {
      char cell[64];
      std::snprintf(cell, sizeof cell, "%.1f%% RMS, median %+.1f%%", 100.0 * e[key]["rms"].get<double>(),
                    100.0 * e[key]["median"].get<double>());
      return std::string(cell);
    };
    out << "\nPredicted against measured: full's rest " << both("full_rest") << "; the method's rest on its stencils "
        << both("mrr_rest") << "; the early estimate of the method from its edges on " << both("mrr_early_estimate")
        << ".\n";
  }
}

// The rule on a frame's counts, as renderFrame takes it: early from H (on the floor, then with the
// edge sample), then from the stencils; its decision as the sweep names it, and what it priced.
struct RuleOnCounts {
  std::string decision;  // mrr, full (on the stencils), full-early, full-floor (SPEC §11)
  nlohmann::json prices;
};
RuleOnCounts ruleOnCounts(const CostModel& model, const Constants& c, const FrameCounts& n) {
  const FallbackDecision early = decideEarly(model, c, n), late = decideFallback(model, c, n);
  RuleOnCounts r;
  r.decision = early.onFloor ? referenceMethod() + "-floor" : early.fellBack ? referenceMethod() + "-early" : late.fellBack ? referenceMethod() : paperMethod();
  r.prices = {{"predicted_full_rest_ms", late.predictedFullMs},
              {"predicted_mrr_rest_ms", late.predictedMrrMs},
              {"predicted_mrr_floor_ms", predictMrrFloorMs(model, c, n)},
              // the early decision's: the floor where it decides, else the larger of the floor and
              // what going on costs
              {"predicted_mrr_early_ms", early.predictedMrrMs},
              // the edge sample's estimate of the method from its edges on (edges, masks, R̂)
              {"predicted_mrr_estimate_ms", predictMrrEstimateMs(model, c, n)}};
  return r;
}

// The counts the rule priced, as a sweep records them (and a replay reads them back).
nlohmann::json countsJson(const FrameCounts& n) {
  return {{"hit", n.hitPixels},
          {"searched", n.searchedPixels},
          {"pcf", n.pcfPixels},
          {"searched_footprint", n.searchedFootprint},
          {"silhouette", n.silhouette},
          {"shaded", n.shaded},
          {"shaded_hit", n.shadedHit},
          {"shaded_searched", n.shadedSearched},
          {"shaded_pcf", n.shadedPcf},
          {"edge_blocks", n.edgeBlocks},
          {"reach", n.reach},
          {"reach_hits", n.reachHits}};
}
FrameCounts countsFromJson(const nlohmann::json& j) {  // throws nlohmann::json::exception on a missing key
  using PerLevel = std::array<int64_t, kLevelCount>;
  FrameCounts n;
  n.hitPixels = j.at("hit");
  n.searchedPixels = j.at("searched");
  n.pcfPixels = j.at("pcf");
  n.searchedFootprint = j.value("searched_footprint", int64_t{0});  // a sweep from before the footprint: none
  n.silhouette = j.at("silhouette").get<PerLevel>();
  n.shaded = j.at("shaded").get<PerLevel>();
  n.shadedHit = j.at("shaded_hit").get<PerLevel>();
  n.shadedSearched = j.at("shaded_searched").get<PerLevel>();
  n.shadedPcf = j.at("shaded_pcf").get<PerLevel>();
  n.edgeBlocks = j.at("edge_blocks");
  n.reach = j.at("reach").get<PerLevel>();
  n.reachHits = j.at("reach_hits").get<PerLevel>();
  return n;
}

// Sizes, effects and sample counts, cycled over the scenes' views: low and high counts, 320×180
// to 1920×1080 (the dearest effects at the smaller sizes, to keep the sweep in minutes).
const std::vector<SweepConfig>& sweepConfigs() {
  static const std::vector<SweepConfig> configs = {
      {Effect::Ssao, 16, 320, 180},  {Effect::Ssm, 196, 1280, 720}, {Effect::Ssgi, 24, 640, 360},
      {Effect::Ssao, 64, 1920, 1080}, {Effect::Ssm, 49, 640, 360},   {Effect::Ssgi, 288, 320, 180},
      {Effect::Ssao, 256, 640, 360}, {Effect::Ssm, 16, 1280, 720},  {Effect::Ssao, 64, 1280, 720},
      {Effect::Ssgi, 80, 640, 360},  {Effect::Ssao, 8, 1920, 1080}, {Effect::Ssm, 324, 320, 180}};
  return configs;
}

}  // namespace

SweepConfig ruleSweepConfig(const std::string& path, size_t frame, size_t framesPerPath) {
  // The oracle's frames take the cycle from its start, the port's from where the oracle's end, as
  // when one run sweeps both: a path's frames are the same whichever --paths the run names.
  const size_t pathOffset = path == "gpu" ? framesPerPath : 0;
  const std::vector<SweepConfig>& configs = sweepConfigs();
  return configs[(pathOffset + frame) % configs.size()];
}

std::string withPathName(std::string file, const std::string& path) {
  if (const auto at = file.find("{path}"); at != std::string::npos) file.replace(at, 6, path);
  return file;
}

CostModel ruleCostModel(const std::string& file, const std::string& path) {
  return file.empty() ? CostModel::defaults(path) : CostModel::fromFile(withPathName(file, path));
}

int runRuleSweep(const RuleSweepOptions& o, const std::vector<BenchPath>& paths, std::ostream& out) {
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = o.threads > 0 ? o.threads : hw;
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  nlohmann::json frames = nlohmann::json::array();
  nlohmann::json models = nlohmann::json::object();  // path → the cost model that decided its frames
  const size_t framesPerPath = o.scenes.size() * kRuleViewCount * static_cast<size_t>(o.configsPerView);
  const size_t total = paths.size() * framesPerPath;
  size_t done = 0;
  const auto start = std::chrono::steady_clock::now();
  for (const BenchPath& path : paths) {
    const CostModel model = ruleCostModel(o.costModelFile, path.name);
    models[path.name] = model.source;
    size_t frameIndex = 0;  // the path's own count: its frames do not depend on the other paths swept
    for (const std::string& sceneName : o.scenes) {
      std::cerr << "[rule-sweep] " << path.name << ": loading " << sceneName << "\n";
      const OpenScene sc = openScene(sceneName, path);
      for (const RuleView& view : ruleViews(*sc.scene, sc.camera, 16.0f / 9.0f))
        for (int k = 0; k < o.configsPerView; ++k) {
          const SweepConfig cfg = ruleSweepConfig(path.name, frameIndex++, framesPerPath);
          const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          std::cerr << "[rule-sweep] " << ++done << "/" << total << "  " << path.name << " " << sceneName << " " << view.name
                    << " " << cfg.width << "x" << cfg.height << " " << toString(cfg.effect) << "-" << cfg.samples << "  ("
                    << static_cast<int>(seconds) << " s)\n";
          const float framed =
              framedSize(*sc.scene, view.camera, static_cast<float>(cfg.width) / static_cast<float>(cfg.height)).size;
          auto constantsFor = [&](const std::string& method) {
            return makeConstants(settingsFor(method, cfg.effect, cfg.width, cfg.height, cfg.samples), framed);
          };
          // full and mrr without the rule, alternating (one warm-up each, then medians), and where
          // the rule falls back the frame with it on, in the same rounds (what a user gets, timed
          // beside full, not apart). The decision is a function of the counts, the same on every
          // run: it is taken after the warm-up. A frame within 10% of break-even gets as many
          // rounds again: its verdict is the one noise sways.
          const Constants cm = constantsFor(paperMethod());
          std::map<std::string, std::vector<double>> fullRuns, mrrRuns, withRuleRuns;
          std::vector<double> pairRatios;  // mrr / full, pair by pair (the two run back to back)
          Measured full, mrr, withRule;
          RuleOnCounts rule;  // taken after the warm-up
          auto runRounds = [&](int rounds, bool warmUp) {
            for (int i = warmUp ? 0 : 1; i <= rounds; ++i) {
              FrameResult ff = sc.render(view.camera, constantsFor(referenceMethod()), {false, {}, nullptr});
              FrameResult fm = sc.render(view.camera, constantsFor(withoutRule()), {false, {}, nullptr, true});
              if (i == 0) rule = ruleOnCounts(model, cm, fm.counts);
              const std::string& decision = rule.decision;
              FrameResult fr;
              if (decision != paperMethod()) fr = sc.render(view.camera, cm, {false, {}, nullptr});
              if (i == 0) continue;
              const std::map<std::string, double> fullStages = stageMs(ff), mrrStages = stageMs(fm);
              for (const auto& [key, v] : fullStages) fullRuns[key].push_back(v);
              for (const auto& [key, v] : mrrStages) mrrRuns[key].push_back(v);
              if (decision != paperMethod())
                for (const auto& [key, v] : stageMs(fr)) withRuleRuns[key].push_back(v);
              pairRatios.push_back(frameMs(mrrStages) / std::max(frameMs(fullStages), 1e-9));
              if (i == rounds) {
                full.last = std::move(ff);
                mrr.last = std::move(fm);
              }
            }
            for (const auto& [key, v] : fullRuns) full.ms[key] = median(v);
            for (const auto& [key, v] : mrrRuns) mrr.ms[key] = median(v);
            for (const auto& [key, v] : withRuleRuns) withRule.ms[key] = median(v);
          };
          runRounds(o.repeats, true);
          const double nearRatio = frameMs(mrr.ms) / std::max(frameMs(full.ms), 1e-9);
          const bool nearBreakEven = nearRatio > kNearBreakEvenLow && nearRatio < kNearBreakEvenHigh;
          if (nearBreakEven) runRounds(o.repeats, false);
          const FrameCounts& n = mrr.last.counts;
          const std::string& decision = rule.decision;
          const double ruleMs = decision == paperMethod() ? frameMs(mrr.ms) : frameMs(withRule.ms);
          const double fullMs = frameMs(full.ms), mrrMs = frameMs(mrr.ms);
          const Verdict verdict = judge(decision, fullMs, mrrMs, pairRatios);
          nlohmann::json frame = {
              {"path", path.name},
              {"scene", sceneName},
              {"view", view.name},
              {"effect", toString(cfg.effect)},
              {"samples", cfg.samples},
              {"width", cfg.width},
              {"height", cfg.height},
              {"hit_share", static_cast<double>(n.hitPixels) / (static_cast<double>(cfg.width) * cfg.height)},
              {"ideal_speedup", mrr.last.idealSpeedup},
              {"ideal_speedup_hit", mrr.last.idealSpeedupHit},
              {"decision", decision},
              {"measured_full_rest_ms", restMs(full.ms)},
              {"measured_mrr_rest_ms", restMs(mrr.ms)},
              {"full_ms", fullMs},
              {"mrr_ms", mrrMs},
              {"rule_ms", ruleMs},
              {"repeats", nearBreakEven ? 2 * o.repeats : o.repeats},
              // the counts the rule priced, and the medians per stage: where a prediction went wrong
              {"counts", countsJson(n)},
              {"full_stages_ms", full.ms},
              {"mrr_stages_ms", mrr.ms},
              {"pair_ratios", pairRatios},
              {"right", verdict.right},
              {"wrong_beyond_noise", verdict.wrongBeyondNoise}};
          frame.update(rule.prices);
          frames.push_back(std::move(frame));
        }
    }
  }
  const nlohmann::json summary = summarize(frames);
  const nlohmann::json result = {{"machine", o.machine}, {"repeats", o.repeats}, {"threads", threads},
                                 {"cost_models", models}, {"summary", summary}, {"frames", frames}};
  if (!o.jsonOut.empty()) writeTextFile(o.jsonOut, result.dump(1) + "\n");
  printSummary(summary, out);
  return 0;
}

int replayRuleSweep(const std::string& sweepFile, const std::string& costModelFile, const std::string& jsonOut,
                    std::ostream& out) {
  const nlohmann::json sweep = readJsonObjectFile(sweepFile, "--rule-replay");
  require(sweep.contains("frames") && sweep["frames"].is_array(),
          "--rule-replay " + sweepFile + ": not a sweep (a JSON object with \"frames\", as --rule-sweep writes)");
  nlohmann::json frames = nlohmann::json::array();
  std::vector<std::string> changed;
  std::map<std::string, CostModel> models;  // by path, each read once
  try {
    for (const nlohmann::json& f : sweep["frames"]) {
      const std::string path = f.at("path");
      require(path == "cpu" || path == "gpu", "--rule-replay " + sweepFile + ": a frame of path \"" + path + "\" (expected cpu or gpu)");
      if (!models.count(path)) models.emplace(path, ruleCostModel(costModelFile, path));
      const CostModel& model = models.at(path);
      const Effect effect = parseEffect(f.at("effect").get<std::string>());
      const int width = f.at("width"), height = f.at("height"), samples = f.at("samples");
      // The rule reads the frame's size, its levels and its sample count, never a world-space
      // constant: the framed size (the automatic radii) does not enter it.
      const Constants c = makeConstants(settingsFor(paperMethod(), effect, width, height, samples), 1.0f);
      const FrameCounts n = countsFromJson(f.at("counts"));
      const RuleOnCounts rule = ruleOnCounts(model, c, n);
      const std::string& decision = rule.decision;
      const double fullMs = f.at("full_ms"), mrrMs = f.at("mrr_ms");
      const Verdict verdict = judge(decision, fullMs, mrrMs, f.at("pair_ratios").get<std::vector<double>>());
      nlohmann::json r = f;
      r["decision"] = decision;
      r.update(rule.prices);
      r["right"] = verdict.right;
      r["wrong_beyond_noise"] = verdict.wrongBeyondNoise;
      // The with-rule time: the method's where it keeps the method, the sweep's where both fall
      // back; unmeasured where only the replay falls back.
      const std::string was = f.at("decision");
      if (decision == paperMethod())
        r["rule_ms"] = mrrMs;
      else if (was == paperMethod())
        r["rule_ms"] = nullptr;
      if (decision != was || verdict.right != f.at("right").get<bool>()) {
        char line[400];
        std::snprintf(line, sizeof line, "| %s | %s | %s | %dx%d %s-%d | %s → %s | %.3f | %s → %s |\n", path.c_str(),
                      f.at("scene").get<std::string>().c_str(), f.at("view").get<std::string>().c_str(), width, height,
                      toString(effect).c_str(), samples, was.c_str(), decision.c_str(), mrrMs / fullMs,
                      f.at("right").get<bool>() ? "right" : "wrong", verdict.right ? "right" : "wrong");
        changed.emplace_back(line);
      }
      frames.push_back(std::move(r));
    }
  } catch (const nlohmann::json::exception& e) {
    throw MrrError("--rule-replay " + sweepFile + ": " + e.what());
  }
  std::vector<std::string> sources;
  for (const auto& [path, model] : models) sources.push_back(path + ": " + model.source);
  out << "Replayed " << frames.size() << " frames of " << sweepFile << " with the cost models of ";
  for (size_t i = 0; i < sources.size(); ++i) out << (i ? "; " : "") << sources[i];
  out << ":\n\n";
  const nlohmann::json summary = summarize(frames);
  if (!jsonOut.empty()) {
    nlohmann::json result = sweep;
    result["summary"] = summary;
    result["frames"] = frames;
    result["replayed_with"] = sources;
    writeTextFile(jsonOut, result.dump(1) + "\n");
  }
  printSummary(summary, out);
  out << "\n" << changed.size() << (changed.size() == 1 ? " frame" : " frames") << " decided or judged otherwise than the sweep recorded"
      << (changed.empty() ? ".\n" : ":\n\n| path | scene | view | frame | decision | mrr/full | verdict |\n|---|---|---|---|---|---|---|\n");
  for (const std::string& line : changed) out << line;
  return 0;
}

}  // namespace mrr
