#include "common/cost_model.h"

#include "common/frame_params.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "common/cost_model_files.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/shader_constants.h"

namespace mrr {

double finerLevelsArea(const Constants& c, const std::array<int64_t, kLevelCount>& n) {
  for (int l = c.coarsestEnabled - 1; l >= 0; --l) {  // j: the coarsest enabled level below k
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (lc.enabled) return static_cast<double>(n[static_cast<size_t>(l)]) * lc.scale * lc.scale;
  }
  return 0.0;
}

double footprintTexels(const LevelConstants& lc, const FrameCounts& n) {
  if (n.searchedPixels <= 0) return 0.0;
  const double mean = static_cast<double>(n.searchedFootprint) / (kFootprintSteps * static_cast<double>(n.searchedPixels));
  return std::min(static_cast<double>(kMaxFootprintTexels), mean * lc.scale);
}

namespace {
double levelPixels(const LevelConstants& lc) { return static_cast<double>(lc.width) * lc.height; }
}  // namespace

double effectMaskNs(const CostModel& m, const Constants& c) {
  return methodInfo(c.mode).masks == MaskBuilder::EffectEdges ? levelPixels(c.levels[0]) * m.nsPerEffectMaskPixel : 0.0;
}

double refineNs(const CostModel& m, const Constants& c) {
  if (!methodInfo(c.mode).aPosteriori || !(c.effectMask.posterior > 0.0f)) return 0.0;
  double ns = 0.0;  // the levels common/driver.cpp refines: enabled, finer than the coarsest, ℓ ≥ ℓ_v
  for (const LevelConstants& lc : c.levels)
    if (lc.enabled && lc.index != c.coarsestEnabled && lc.index >= c.effectMask.posteriorFinest)
      ns += levelPixels(lc) * m.nsPerRefinePixel;
  return ns;
}

namespace {
double shadeNs(const EffectCost& e, int samples) { return e.nsPerShadedPixel + e.nsPerSample * samples; }
// SPEC §11: a + b N + ν f_ℓ, in ns: a searching level-ℓ pixel on geometry, before its PCF.
double searchNs(const EffectCost& e, const Constants& c, const LevelConstants& lc, const FrameCounts& n) {
  return shadeNs(e, c.samples()) + e.nsPerFootprintTexel * footprintTexels(lc, n);
}
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

// SPEC §11: s_ℓ = 1 + (s − 1)(1 − q_ℓ), q_ℓ = |S_ℓ ∩ searched| s_ℓ² / H_a: the premium of a
// stencilled pixel over a dense frame's falls with the share of the level's paying pixels the
// stencil covers. A stencil takes the dearest pixels first (at edges: samples find occluders,
// branches diverge, the walk is sparse); one that covers the whole level is the dense frame,
// whose mean the full fit prices (q = 1: factor 1). The pixels taken first cost s times that
// mean, the ones taken last 2 − s times it, so s ≤ 2 (the calibration clamps it) and a level's
// cost rises with |S_ℓ| whatever s.
double sparseFactorAt(const EffectCost& e, const LevelConstants& lc, double shadedSearched, const FrameCounts& n) {
  const double levelSearched = static_cast<double>(n.searchedPixels) / (static_cast<double>(lc.scale) * lc.scale);
  const double q = levelSearched > 0.0 ? std::min(1.0, shadedSearched / levelSearched) : 1.0;
  return 1.0 + (e.sparseFactor - 1.0) * (1.0 - q);
}

// SPEC §11: W·H ρ, in ns: the rule's own counts (and SSM's sample), paid by the method alone.
double ruleNs(const EffectCost& e, const Constants& c) { return static_cast<double>(c.width) * c.height * e.nsPerRulePixel; }

// SPEC §11: P_0 (ε + μ) + H ε_h + A μ_A (+ P_0 μ_e, mrr-effect), in ns: the edges and the masks
// (A: the edge sample's reach, 0 for the floor).
double edgesMasksNs(const CostModel& m, const Constants& c, const FrameCounts& n, double reach) {
  return levelPixels(c.levels[0]) * (m.nsPerEdgePixel + m.nsPerMaskPixel) +
         static_cast<double>(n.hitPixels) * m.nsPerEdgeHitPixel + reach * m.nsPerMaskReachPixel + effectMaskNs(m, c);
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
  // common/cost_models/<path>.json, compiled in (common/embed_cost_models.cmake): what
  // `mrr bench --calibrate` wrote on this project's CI machine (common/cost_models/README.md).
  // Parsed once per path; a file that does not parse fails the build's tests, not a render.
  static const std::vector<std::pair<std::string, CostModel>> parsed = [] {
    std::vector<std::pair<std::string, CostModel>> models;
    for (const CostModelFile& f : kCostModelFiles) {
      const nlohmann::json j = nlohmann::json::parse(f.text, nullptr, false);
      const std::string where = "common/cost_models/" + std::string(f.path) + ".json (built in)";
      if (j.is_discarded() || !j.is_object()) throw MrrError(where + ": not a JSON object");
      models.emplace_back(f.path, fromJson(j, where));
    }
    return models;
  }();
  std::string known;
  for (const auto& [name, model] : parsed) {
    if (name == path) return model;
    known += (known.empty() ? "" : ", ") + name;
  }
  throw MrrError("no built-in cost model for path '" + path + "' (common/cost_models/ has " + known + ")");
}

CostModel CostModel::fromJson(const nlohmann::json& j, const std::string& origin) {
  CostModel m;
  try {
    m.source = j.value("source", optionName(Param::CostModel));
    for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
      const nlohmann::json& ej = j.at("effects").at(toString(e));
      EffectCost& ec = m.effect[static_cast<size_t>(e)];
      ec.nsPerShadedPixel = ej.at("ns_per_shaded_pixel").get<double>();
      ec.nsPerSample = ej.at("ns_per_sample").get<double>();
      ec.nsPerLevelPixel = ej.at("ns_per_level_pixel").get<double>();
      ec.nsPerBackgroundPixel = ej.at("ns_per_background_pixel").get<double>();
      ec.nsPerPcfSample = ej.at("ns_per_pcf_sample").get<double>();
      ec.sparseFactor = ej.at("sparse_factor").get<double>();
      if (!(ec.sparseFactor >= kMinSparseFactor && ec.sparseFactor <= kMaxSparseFactor))
        throw MrrError(origin + ": effects." + toString(e) + ".sparse_factor: " + std::to_string(ec.sparseFactor) +
                       " is outside [1, 2] (SPEC §11)");
      ec.fixedMs = ej.at("fixed_ms").get<double>();
      ec.fullFixedMs = ej.at("full_fixed_ms").get<double>();
      ec.nsPerRulePixel = ej.at("ns_per_rule_pixel").get<double>();
      ec.nsPerFootprintTexel = ej.at("ns_per_footprint_texel").get<double>();
      if (!(ec.nsPerFootprintTexel >= 0.0) || !std::isfinite(ec.nsPerFootprintTexel))
        throw MrrError(origin + ": effects." + toString(e) + ".ns_per_footprint_texel: " +
                       std::to_string(ec.nsPerFootprintTexel) + " is not a number >= 0 (SPEC §11)");
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
    // φ_ℓ and η_ℓ: a number for every level below the coarsest; η_ℓ a positive one (SPEC §11)
    auto perLevel = [&](const char* key, std::array<double, kLevelCount - 1>& into) {
      const nlohmann::json& v = j.at(key);
      if (!v.is_array() || v.size() != into.size())
        throw MrrError(origin + ": " + key + ": expected " + std::to_string(into.size()) + " numbers (levels 0-2)");
      for (size_t l = 0; l < into.size(); ++l) into[l] = v.at(l).get<double>();
    };
    perLevel("stencil_fill", m.stencilFill);
    perLevel("edge_band_fill", m.edgeBandFill);
    for (double band : m.edgeBandFill)
      if (!(band > 0.0) || !std::isfinite(band))
        throw MrrError(origin + ": edge_band_fill: " + std::to_string(band) + " is not a positive number (SPEC §11)");
    m.estimateSpread = j.at("estimate_spread").get<double>();
    m.nsPerEffectMaskPixel = j.at("ns_per_effect_mask_pixel").get<double>();
    m.nsPerRefinePixel = j.at("ns_per_refine_pixel").get<double>();
  } catch (const nlohmann::json::exception& e) {
    throw MrrError(origin + ": " + e.what());
  }
  return m;
}

CostModel CostModel::fromFile(const std::string& file) {
  return fromJson(readJsonObjectFile(file, optionName(Param::CostModel)), optionName(Param::CostModel) + " " + file);
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
                            {"ns_per_rule_pixel", ec.nsPerRulePixel},
                            {"ns_per_footprint_texel", ec.nsPerFootprintTexel}};
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
          {"edge_band_fill", edgeBandFill},
          {"estimate_spread", estimateSpread},
          {"edges_masks_fixed_ms", edgesMasksFixedMs},
          {"ns_per_effect_mask_pixel", nsPerEffectMaskPixel},
          {"ns_per_refine_pixel", nsPerRefinePixel}};
}

// SPEC §11: H_a (a + b N + ν f_0) + H_p e N + (W·H − H_a) c + P_0 (H / W·H) d + W·H β₀ + k₀, in ms.
double predictFullMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  const double paying = static_cast<double>(n.searchedPixels);
  const double rest = std::max(0.0, static_cast<double>(c.width) * c.height - paying);
  return (paying * searchNs(e, c, c.levels[0], n) + static_cast<double>(n.pcfPixels) * e.nsPerPcfSample * c.samples() +
          rest * e.nsPerBackgroundPixel + levelPassNs(e, c.levels[0], c, n) +
          static_cast<double>(c.width) * c.height * m.nsPerFullBlendPixel) *
             1e-6 +
         e.fullFixedMs;
}

// SPEC §11: Σ_ℓ shaded ((|S_ℓ ∩ searched| (a + b N + ν f_ℓ) + |S_ℓ ∩ pcf| e N) s + |S_ℓ \ searched| c +
// P_ℓ (H / W·H) d) + the coarse G-buffers and the blend (its finer levels over |S_j|) + W·H ρ + k,
// in ms.
double predictMrrMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  double ns = coarseGbuffersAndBlendNs(m, c) + fineBlendNs(m, c, n.shaded) + ruleNs(e, c) + refineNs(m, c);
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled || !lc.shaded) continue;
    const auto l = static_cast<size_t>(lc.index);
    const double paying = static_cast<double>(n.shadedSearched[l]);
    const double off = std::max(0.0, static_cast<double>(n.shaded[l]) - paying);
    const double pcf = static_cast<double>(n.shadedPcf[l]) * e.nsPerPcfSample * c.samples();
    ns += (paying * searchNs(e, c, lc, n) + pcf) * sparseFactorAt(e, lc, paying, n) + off * e.nsPerBackgroundPixel +
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
  // What `count` shaded pixels of level lc pay, where a share of them pays the effect (a, b),
  // another share PCF (e N), both at the level's sparse factor, and the rest leaves at once (c).
  auto shadedNs = [&](const LevelConstants& lc, double count, double searchedShare, double pcfShare) {
    const double factor = sparseFactorAt(e, lc, count * searchedShare, n);
    return count * ((searchedShare * searchNs(e, c, lc, n) + pcfShare * e.nsPerPcfSample * c.samples()) * factor +
                    (1.0 - searchedShare) * e.nsPerBackgroundPixel);
  };
  const double perPixelSearched = static_cast<double>(n.searchedPixels) / pixels, perPixelPcf = static_cast<double>(n.pcfPixels) / pixels;
  const double hits = std::max(1.0, static_cast<double>(n.hitPixels));
  const double perHitSearched = static_cast<double>(n.searchedPixels) / hits, perHitPcf = static_cast<double>(n.pcfPixels) / hits;
  double ns = edgesMasksNs(m, c, n, 0.0) + coarseGbuffersAndBlendNs(m, c) + fineBlendNs(m, c, n.silhouette) + ruleNs(e, c) +
              refineNs(m, c);
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled || !lc.shaded) continue;
    const auto l = static_cast<size_t>(lc.index);
    ns += levelPassNs(e, lc, c, n);  // every shaded level pays d
    if (lc.index == c.coarsestEnabled)
      ns += shadedNs(lc, levelPixels(lc), perPixelSearched, perPixelPcf);  // S_k = 1 everywhere
    else if (lc.index == 0)
      ns += shadedNs(lc, static_cast<double>(n.silhouette[l]), perHitSearched, perHitPcf);
    else
      ns += shadedNs(lc, static_cast<double>(n.silhouette[l]), perPixelSearched, perPixelPcf);
  }
  return ns * 1e-6 + m.edgesMasksFixedMs + e.fixedMs;
}

double estimateStencilPixels(double fill, double bandFill, const LevelConstants& lc, const FrameCounts& n) {
  const auto l = static_cast<size_t>(lc.index);
  const double blockPixels = static_cast<double>(kEdgeSampleStep) * kEdgeSampleStep / (static_cast<double>(lc.scale) * lc.scale);
  const double band = bandFill * static_cast<double>(n.edgeBlocks) * blockPixels;  // η |Ê| (8 / s_ℓ)²
  return std::max(static_cast<double>(n.silhouette[l]), std::min(fill * static_cast<double>(n.reach[l]), band));
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
      const size_t fl = std::min(l, m.stencilFill.size() - 1);
      shaded = estimateStencilPixels(m.stencilFill[fl], m.edgeBandFill[fl], lc, n);
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
