#include "common/cost_model.h"

#include <algorithm>
#include <cmath>

#include "common/error.h"

namespace mrr {

double finerLevelsArea(const Constants& c, const std::array<int64_t, kLevelCount>& n) {
  for (int l = c.coarsestEnabled - 1; l >= 0; --l) {  // j: the coarsest enabled level below k
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (lc.enabled) return static_cast<double>(n[static_cast<size_t>(l)]) * lc.scale * lc.scale;
  }
  return 0.0;
}

namespace {
double levelPixels(const LevelConstants& lc) { return static_cast<double>(lc.width) * lc.height; }
double shadeNs(const EffectCost& e, int samples) { return e.nsPerShadedPixel + e.nsPerSample * samples; }
const EffectCost& effectCost(const CostModel& m, const Constants& c) { return m.effect[static_cast<size_t>(c.effect)]; }
// H / W·H: the share of the frame on geometry, taken for every level's.
double hitShare(const Constants& c, const FrameCounts& n) {
  return static_cast<double>(n.hitPixels) / std::max(1.0, static_cast<double>(c.width) * c.height);
}

// SPEC §11: P_ℓ (H / W·H) d, in ns: a shaded level's per-pixel pass (SSAO's occluder planes,
// SSGI's direct light), paid by its pixels on geometry.
double levelPassNs(const EffectCost& e, const LevelConstants& lc, const Constants& c, const FrameCounts& n) {
  return levelPixels(lc) * hitShare(c, n) * e.nsPerLevelPixel;
}

// SPEC §11: n_j s_j² β_f, in ns: the blend's finer levels where they can show, n_j = |S_j| (or, for
// the floor, the silhouettes B_j ⊆ S_j).
double fineBlendNs(const CostModel& m, const Constants& c, const std::array<int64_t, kLevelCount>& n) {
  return finerLevelsArea(c, n) * m.nsPerFineBlendPixel;
}

// SPEC §11: W·H ρ, in ns: the rule's own counts (and SSM's sample), paid by the method alone.
double ruleNs(const EffectCost& e, const Constants& c) { return static_cast<double>(c.width) * c.height * e.nsPerRulePixel; }

// SPEC §11: P_0 (ε + μ) + H ε_h + A μ_A, in ns: the edges and the masks (A: the edge sample's
// reach, 0 for the floor).
double edgesMasksNs(const CostModel& m, const Constants& c, const FrameCounts& n, double reach) {
  return levelPixels(c.levels[0]) * (m.nsPerEdgePixel + m.nsPerMaskPixel) +
         static_cast<double>(n.hitPixels) * m.nsPerEdgeHitPixel + reach * m.nsPerMaskReachPixel;
}

// SPEC §11: Σ_{ℓ≥1 enabled} P_ℓ g + W·H (β₀ + β), in ns: what the method pays beyond shading
// whatever its stencils.
double coarseGbuffersAndBlendNs(const CostModel& m, const Constants& c) {
  double ns = static_cast<double>(c.width) * c.height * (m.nsPerFullBlendPixel + m.nsPerBlendPixel);
  for (const LevelConstants& lc : c.levels)
    if (lc.enabled && lc.index > 0) ns += levelPixels(lc) * m.nsPerCoarseGbufferPixel;
  return ns;
}
}  // namespace

CostModel CostModel::defaults(const std::string& path) {
  CostModel m;
  // `mrr bench --calibrate FILE --paths cpu gpu` on the CI machine (2-core AMD EPYC VM; the
  // port on llvmpipe, LLVM 15): docs/figures.md. Order: ssao, ssm, ssgi; {a, b, d, c, e, s, k, k₀, ρ}.
  if (path == "gpu") {
    // gpu: one run (--repeats 5) of the GPU-resident port on llvmpipe (2026-11-24, evening: the
    // rule's counts made faster, the edge sample skipped where the floor decides).
    m.source = "built-in default (gpu: llvmpipe on the 2-core AMD EPYC CI VM)";
    m.effect = {EffectCost{209.2, 5.236, 0, 24.63, 0, 1.177, 1.831, 0.4529, 6.96},
                EffectCost{157.3, 0, 0, 31.59, 1.643, 1.249, 1.726, 0.3848, 9.803},
                EffectCost{20.55, 6.905, 10.93, 18.07, 0, 1.132, 3.957, 1.041, 6.32}};
    m.nsPerCoarseGbufferPixel = 14.82;
    m.nsPerFullBlendPixel = 4.585;
    m.nsPerBlendPixel = 1.984;
    m.nsPerFineBlendPixel = 32.67;
    m.nsPerEdgePixel = 10.6;
    m.nsPerEdgeHitPixel = 8.6;
    m.nsPerMaskPixel = 4.038;
    m.nsPerMaskReachPixel = 28.55;
    m.stencilFill = {0.7148, 0.8409, 0.9584};
    m.estimateSpread = 0.327;
    m.edgesMasksFixedMs = 0.8624;
  } else {
    // cpu: one run (--repeats 5, the same evening and code as the port's).
    m.source = "built-in default (cpu: 2 threads on the 2-core AMD EPYC CI VM)";
    m.effect = {EffectCost{203, 8.892, 1.104, 3.058, 0, 1.077, 0.1767, 0.02992, 2.581},
                EffectCost{76.1, 0, 0, 2.486, 1.542, 1.16, 0.2254, 0.01498, 3.145},
                EffectCost{30.51, 10.8, 16.92, 3.537, 0, 1.317, 0.3556, 0.08116, 2.296}};
    m.nsPerCoarseGbufferPixel = 7.341;
    m.nsPerFullBlendPixel = 3.788;
    m.nsPerBlendPixel = 1.9;
    m.nsPerFineBlendPixel = 1.471;
    m.nsPerEdgePixel = 1.162;
    m.nsPerEdgeHitPixel = 3.88;
    m.nsPerMaskPixel = 2.633;
    m.nsPerMaskReachPixel = 0.1937;
    m.stencilFill = {0.7148, 0.8409, 0.9584};
    m.estimateSpread = 0.4118;
    m.edgesMasksFixedMs = 0.06254;
  }
  return m;
}

CostModel CostModel::fromJson(const nlohmann::json& j) {
  CostModel m;
  try {
    m.source = j.value("source", std::string("--cost-model"));
    for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
      const nlohmann::json& ej = j.at("effects").at(toString(e));
      EffectCost& ec = m.effect[static_cast<size_t>(e)];
      ec.nsPerShadedPixel = ej.at("ns_per_shaded_pixel").get<double>();
      ec.nsPerSample = ej.at("ns_per_sample").get<double>();
      ec.nsPerLevelPixel = ej.at("ns_per_level_pixel").get<double>();
      ec.nsPerBackgroundPixel = ej.at("ns_per_background_pixel").get<double>();
      ec.nsPerPcfSample = ej.at("ns_per_pcf_sample").get<double>();
      ec.sparseFactor = ej.at("sparse_factor").get<double>();
      ec.fixedMs = ej.at("fixed_ms").get<double>();
      ec.fullFixedMs = ej.at("full_fixed_ms").get<double>();
      ec.nsPerRulePixel = ej.at("ns_per_rule_pixel").get<double>();
    }
    m.nsPerCoarseGbufferPixel = j.at("ns_per_coarse_gbuffer_pixel").get<double>();
    m.edgesMasksFixedMs = j.at("edges_masks_fixed_ms").get<double>();
    m.nsPerBlendPixel = j.at("ns_per_blend_pixel").get<double>();
    m.nsPerFineBlendPixel = j.at("ns_per_fine_blend_pixel").get<double>();
    m.nsPerFullBlendPixel = j.at("ns_per_full_blend_pixel").get<double>();
    m.nsPerEdgePixel = j.at("ns_per_edge_pixel").get<double>();
    m.nsPerEdgeHitPixel = j.at("ns_per_edge_hit_pixel").get<double>();
    m.nsPerMaskPixel = j.at("ns_per_mask_pixel").get<double>();
    m.nsPerMaskReachPixel = j.at("ns_per_mask_reach_pixel").get<double>();
    const nlohmann::json& fill = j.at("stencil_fill");
    if (!fill.is_array() || fill.size() != m.stencilFill.size())
      throw MrrError("--cost-model: stencil_fill: expected " + std::to_string(m.stencilFill.size()) + " numbers (levels 0-2)");
    for (size_t l = 0; l < m.stencilFill.size(); ++l) m.stencilFill[l] = fill.at(l).get<double>();
    m.estimateSpread = j.at("estimate_spread").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw MrrError(std::string("--cost-model: ") + e.what());
  }
  return m;
}

nlohmann::json CostModel::toJson() const {
  nlohmann::json effects;
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
    const EffectCost& ec = effect[static_cast<size_t>(e)];
    effects[toString(e)] = {{"ns_per_shaded_pixel", ec.nsPerShadedPixel},
                            {"ns_per_sample", ec.nsPerSample},
                            {"ns_per_level_pixel", ec.nsPerLevelPixel},
                            {"ns_per_background_pixel", ec.nsPerBackgroundPixel},
                            {"ns_per_pcf_sample", ec.nsPerPcfSample},
                            {"sparse_factor", ec.sparseFactor},
                            {"fixed_ms", ec.fixedMs},
                            {"full_fixed_ms", ec.fullFixedMs},
                            {"ns_per_rule_pixel", ec.nsPerRulePixel}};
  }
  return {{"source", source},
          {"effects", effects},
          {"ns_per_coarse_gbuffer_pixel", nsPerCoarseGbufferPixel},
          {"ns_per_blend_pixel", nsPerBlendPixel},
          {"ns_per_fine_blend_pixel", nsPerFineBlendPixel},
          {"ns_per_full_blend_pixel", nsPerFullBlendPixel},
          {"ns_per_edge_pixel", nsPerEdgePixel},
          {"ns_per_edge_hit_pixel", nsPerEdgeHitPixel},
          {"ns_per_mask_pixel", nsPerMaskPixel},
          {"ns_per_mask_reach_pixel", nsPerMaskReachPixel},
          {"stencil_fill", stencilFill},
          {"estimate_spread", estimateSpread},
          {"edges_masks_fixed_ms", edgesMasksFixedMs}};
}

// SPEC §11: H_a (a + b N) + H_p e N + (W·H − H_a) c + P_0 (H / W·H) d + W·H β₀ + k₀, in ms.
double predictFullMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  const double paying = static_cast<double>(n.searchedPixels);
  const double rest = std::max(0.0, static_cast<double>(c.width) * c.height - paying);
  return (paying * shadeNs(e, c.samples()) + static_cast<double>(n.pcfPixels) * e.nsPerPcfSample * c.samples() +
          rest * e.nsPerBackgroundPixel + levelPassNs(e, c.levels[0], c, n) +
          static_cast<double>(c.width) * c.height * m.nsPerFullBlendPixel) *
             1e-6 +
         e.fullFixedMs;
}

// SPEC §11: Σ_ℓ shaded ((|S_ℓ ∩ searched| (a + b N) + |S_ℓ ∩ pcf| e N) s + |S_ℓ \ searched| c +
// P_ℓ (H / W·H) d) + the coarse G-buffers and the blend (its finer levels over |S_j|) + W·H ρ + k,
// in ms.
double predictMrrMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  double ns = coarseGbuffersAndBlendNs(m, c) + fineBlendNs(m, c, n.shaded) + ruleNs(e, c);
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled || !lc.shaded) continue;
    const auto l = static_cast<size_t>(lc.index);
    const double paying = static_cast<double>(n.shadedSearched[l]);
    const double off = std::max(0.0, static_cast<double>(n.shaded[l]) - paying);
    const double pcf = static_cast<double>(n.shadedPcf[l]) * e.nsPerPcfSample * c.samples();
    ns += (paying * shadeNs(e, c.samples()) + pcf) * e.sparseFactor + off * e.nsPerBackgroundPixel +
          levelPassNs(e, lc, c, n);
  }
  return ns * 1e-6 + e.fixedMs;
}

// SPEC §11: P_0 (ε + μ) + H ε_h + κ + the coarse G-buffers and the blend (B_j for |S_j|) + W·H ρ + Σ_ℓ shaded P_ℓ (H / W·H) d
// + |B_0| (what a pixel on geometry pays on average) + Σ_{0<ℓ<k} |B_ℓ| (what a pixel pays on
// average) + P_k (((H_a (a + b N) + H_p e N) / W·H) s + (1 − H_a / W·H) c) for the coarsest
// enabled level k + k, in ms.
double predictMrrFloorMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  const double pixels = std::max(1.0, static_cast<double>(c.width) * c.height);
  // What one shaded pixel pays on average, where a share of the pixels pays the effect (a, b),
  // another share PCF (e N) at the sparse factor, and the rest leaves at once (c).
  auto averageNs = [&](double searchedShare, double pcfShare) {
    return (searchedShare * shadeNs(e, c.samples()) + pcfShare * e.nsPerPcfSample * c.samples()) * e.sparseFactor +
           (1.0 - searchedShare) * e.nsPerBackgroundPixel;
  };
  const double perPixel = averageNs(static_cast<double>(n.searchedPixels) / pixels, static_cast<double>(n.pcfPixels) / pixels);
  const double hits = std::max(1.0, static_cast<double>(n.hitPixels));
  const double perHit = averageNs(static_cast<double>(n.searchedPixels) / hits, static_cast<double>(n.pcfPixels) / hits);
  double ns = edgesMasksNs(m, c, n, 0.0) + coarseGbuffersAndBlendNs(m, c) + fineBlendNs(m, c, n.silhouette) + ruleNs(e, c);
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled || !lc.shaded) continue;
    const auto l = static_cast<size_t>(lc.index);
    ns += levelPassNs(e, lc, c, n);  // every shaded level pays d
    if (lc.index == c.coarsestEnabled)
      ns += levelPixels(lc) * perPixel;  // S_k = 1 everywhere
    else
      ns += static_cast<double>(n.silhouette[l]) * (lc.index == 0 ? perHit : perPixel);
  }
  return ns * 1e-6 + m.edgesMasksFixedMs + e.fixedMs;
}

FrameCounts estimateStencils(const CostModel& m, const Constants& c, const FrameCounts& n) {
  FrameCounts est = n;
  const double hits = std::max(1.0, static_cast<double>(n.hitPixels));
  const double searchedShare = static_cast<double>(n.searchedPixels) / hits, pcfShare = static_cast<double>(n.pcfPixels) / hits;
  for (const LevelConstants& lc : c.levels) {
    const auto l = static_cast<size_t>(lc.index);
    est.shaded[l] = est.shadedHit[l] = est.shadedSearched[l] = est.shadedPcf[l] = 0;
    if (!lc.enabled || !lc.shaded) continue;
    double shaded = 0.0, onGeometryShare = 0.0;
    if (lc.index == c.coarsestEnabled) {  // S_k = 1 everywhere
      shaded = levelPixels(lc);
      onGeometryShare = hitShare(c, n);
    } else {
      const double reach = static_cast<double>(n.reach[l]);
      shaded = std::max(static_cast<double>(n.silhouette[l]), m.stencilFill[std::min(l, m.stencilFill.size() - 1)] * reach);
      const double reachFullRes = reach * lc.scale * lc.scale;
      // silhouettes alone (no reach): half on geometry
      onGeometryShare = reachFullRes > 0.0 ? static_cast<double>(n.reachHits[l]) / reachFullRes : 0.5;
    }
    const double onGeometry = shaded * std::min(1.0, onGeometryShare);
    est.shaded[l] = std::llround(shaded);
    est.shadedHit[l] = std::llround(onGeometry);
    est.shadedSearched[l] = std::llround(onGeometry * searchedShare);
    est.shadedPcf[l] = std::llround(onGeometry * pcfShare);
  }
  return est;
}

double predictEdgesMasksMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  double reach = 0.0;
  for (int64_t v : n.reach) reach += static_cast<double>(v);
  return edgesMasksNs(m, c, n, reach) * 1e-6 + m.edgesMasksFixedMs;
}

double predictMrrEstimateMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  return predictEdgesMasksMs(m, c, n) + predictMrrMs(m, c, estimateStencils(m, c, n));
}

double predictContinuingMs(const CostModel& m, const Constants& c, const FrameCounts& n, double fullMs) {
  const double rest = predictMrrMs(m, c, estimateStencils(m, c, n));
  const double lo = rest * (1.0 - m.estimateSpread), hi = rest * (1.0 + m.estimateSpread);
  double expectedMin = std::min(rest, fullMs);  // E[min(R, F)], R uniform on [lo, hi]
  if (hi > lo && fullMs > lo && fullMs < hi)
    expectedMin = (0.5 * (fullMs * fullMs - lo * lo) + fullMs * (hi - fullMs)) / (hi - lo);
  else if (hi > lo && fullMs <= lo)
    expectedMin = fullMs;
  return predictEdgesMasksMs(m, c, n) + expectedMin;
}

namespace {
FallbackDecision decide(const CostModel& m, double fullMs, double mrrMs, bool early) {
  FallbackDecision d;
  d.evaluated = true;
  d.early = early;
  d.predictedFullMs = fullMs;
  d.predictedMrrMs = mrrMs;
  d.fellBack = fullMs - mrrMs <= 0.0;
  d.costModel = m.source;
  return d;
}
}  // namespace

FallbackDecision decideOnFloor(const CostModel& m, const Constants& c, const FrameCounts& n) {
  FallbackDecision d = decide(m, predictFullMs(m, c, n), predictMrrFloorMs(m, c, n), true);
  d.onFloor = d.fellBack;
  return d;
}

FallbackDecision decideEarly(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const FallbackDecision floor = decideOnFloor(m, c, n);
  if (floor.fellBack) return floor;  // whatever the edge sample says: max(floor, ·) ≥ floor ≥ full
  const double fullMs = floor.predictedFullMs;
  return decide(m, fullMs, std::max(floor.predictedMrrMs, predictContinuingMs(m, c, n, fullMs)), true);
}

FallbackDecision decideFallback(const CostModel& m, const Constants& c, const FrameCounts& n) {
  return decide(m, predictFullMs(m, c, n), predictMrrMs(m, c, n), false);
}

}  // namespace mrr
