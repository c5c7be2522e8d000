#include "common/cost_model.h"

#include <algorithm>

#include "common/error.h"

namespace mrr {

namespace {
double levelPixels(const LevelConstants& lc) { return static_cast<double>(lc.width) * lc.height; }
double shadeNs(const EffectCost& e, int samples) { return e.nsPerShadedPixel + e.nsPerSample * samples; }
const EffectCost& effectCost(const CostModel& m, const Constants& c) { return m.effect[static_cast<size_t>(c.effect)]; }
// H / W·H: the share of the frame on geometry, taken for every level's.
double hitShare(const Constants& c, const FrameCounts& n) {
  return static_cast<double>(n.hitPixels) / std::max(1.0, static_cast<double>(c.width) * c.height);
}

// SPEC §11: Σ_{ℓ≥1 enabled} (P_ℓ g + P_ℓ (H / W·H) h + T t) + W·H β, in ns: what the method
// pays beyond shading whatever its stencils.
double coarseGbuffersAndBlendNs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  double ns = static_cast<double>(c.width) * c.height * m.nsPerBlendPixel;
  for (const LevelConstants& lc : c.levels)
    if (lc.enabled && lc.index > 0)
      ns += levelPixels(lc) * (m.nsPerCoarseGbufferPixel + hitShare(c, n) * m.nsPerCoarseGbufferHit) +
            static_cast<double>(n.triangles) * m.nsPerTrianglePerLevel;
  return ns;
}
}  // namespace

CostModel CostModel::defaults(const std::string& path) {
  CostModel m;
  // `mrr bench --calibrate FILE --paths cpu gpu` on the CI machine (2-core AMD EPYC VM; the
  // port on llvmpipe, LLVM 15): docs/figures.md. Order: ssao, ssm, ssgi; {a, b, d, c, e, s}.
  if (path == "gpu") {
    // gpu: the mean of two runs (--repeats 3) of the GPU-resident port on llvmpipe (2026-11-24).
    m.source = "built-in default (gpu: llvmpipe on the 2-core AMD EPYC CI VM)";
    m.effect = {EffectCost{257.1, 6.02, 0.0, 37.2, 0.0, 1.09},
                EffectCost{188.7, 0.51, 0.0, 42.6, 0.0, 2.27},
                EffectCost{51.2, 8.78, 19.2, 24.6, 0.0, 1.00}};
    m.nsPerCoarseGbufferPixel = 0.0;
    m.nsPerCoarseGbufferHit = 76.8;
    m.nsPerTrianglePerLevel = 93.13;
    m.nsPerBlendPixel = 25.3;
    m.nsPerEdgePixel = 22.7;
    m.nsPerMaskPixel = 20.6;
  } else {
    // cpu: the mean of two runs (--repeats 5), which agreed within 10% (2026-11-24).
    m.source = "built-in default (cpu: 2 threads on the 2-core AMD EPYC CI VM)";
    m.effect = {EffectCost{189.0, 5.44, 0.9, 3.5, 0.0, 1.17},
                EffectCost{62.0, 0.00, 0.0, 2.8, 47.4, 1.03},
                EffectCost{31.2, 8.40, 14.2, 4.0, 0.0, 1.81}};
    m.nsPerCoarseGbufferPixel = 12.3;
    m.nsPerCoarseGbufferHit = 15.8;
    m.nsPerTrianglePerLevel = 4.83;
    m.nsPerBlendPixel = 6.1;
    m.nsPerEdgePixel = 3.6;
    m.nsPerMaskPixel = 3.5;
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
      ec.nsPerShadowedSample = ej.at("ns_per_shadowed_sample").get<double>();
      ec.sparseFactor = ej.at("sparse_factor").get<double>();
    }
    m.nsPerCoarseGbufferPixel = j.at("ns_per_coarse_gbuffer_pixel").get<double>();
    m.nsPerCoarseGbufferHit = j.at("ns_per_coarse_gbuffer_hit").get<double>();
    m.nsPerTrianglePerLevel = j.at("ns_per_triangle_per_level").get<double>();
    m.nsPerBlendPixel = j.at("ns_per_blend_pixel").get<double>();
    m.nsPerEdgePixel = j.at("ns_per_edge_pixel").get<double>();
    m.nsPerMaskPixel = j.at("ns_per_mask_pixel").get<double>();
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
                            {"ns_per_shadowed_sample", ec.nsPerShadowedSample},
                            {"sparse_factor", ec.sparseFactor}};
  }
  return {{"source", source},
          {"effects", effects},
          {"ns_per_coarse_gbuffer_pixel", nsPerCoarseGbufferPixel},
          {"ns_per_coarse_gbuffer_hit", nsPerCoarseGbufferHit},
          {"ns_per_triangle_per_level", nsPerTrianglePerLevel},
          {"ns_per_blend_pixel", nsPerBlendPixel},
          {"ns_per_edge_pixel", nsPerEdgePixel},
          {"ns_per_mask_pixel", nsPerMaskPixel}};
}

// SPEC §11: H (a + b N) + H_s e N + (W·H − H) c + P_0 d, in ms.
double predictFullMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  const double hit = static_cast<double>(n.hitPixels);
  const double background = std::max(0.0, static_cast<double>(c.width) * c.height - hit);
  return (hit * shadeNs(e, c.samples()) + static_cast<double>(n.shadowedPixels) * e.nsPerShadowedSample * c.samples() +
          background * e.nsPerBackgroundPixel + levelPixels(c.levels[0]) * e.nsPerLevelPixel) *
         1e-6;
}

// SPEC §11: Σ_ℓ shaded (|S_ℓ ∩ hit| (a + b N) s + |S_ℓ \ hit| c + P_ℓ d) + the coarse
// G-buffers and the blend, in ms.
double predictMrrMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  double ns = coarseGbuffersAndBlendNs(m, c, n);
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled || !lc.shaded) continue;
    const auto l = static_cast<size_t>(lc.index);
    const double onGeometry = static_cast<double>(n.shadedHit[l]);
    const double off = std::max(0.0, static_cast<double>(n.shaded[l]) - onGeometry);
    const double shadowed = static_cast<double>(n.shadedShadowed[l]) * e.nsPerShadowedSample * c.samples();
    ns += (onGeometry * shadeNs(e, c.samples()) + shadowed) * e.sparseFactor + off * e.nsPerBackgroundPixel +
          levelPixels(lc) * e.nsPerLevelPixel;
  }
  return ns * 1e-6;
}

// SPEC §11: P_0 (ε + μ) + the coarse G-buffers and the blend + P_k (((H (a + b N) + H_s e N) /
// W·H) s + (1 − H / W·H) c + d) for the coarsest enabled level k, in ms.
double predictMrrFloorMs(const CostModel& m, const Constants& c, const FrameCounts& n) {
  const EffectCost& e = effectCost(m, c);
  const LevelConstants& coarsest = c.levels[static_cast<size_t>(c.coarsestEnabled)];
  const double share = hitShare(c, n);
  double ns = levelPixels(c.levels[0]) * (m.nsPerEdgePixel + m.nsPerMaskPixel) + coarseGbuffersAndBlendNs(m, c, n);
  const double shadowShare = static_cast<double>(n.shadowedPixels) / std::max(1.0, static_cast<double>(c.width) * c.height);
  ns += levelPixels(coarsest) *
        ((share * shadeNs(e, c.samples()) + shadowShare * e.nsPerShadowedSample * c.samples()) * e.sparseFactor +
         (1.0 - share) * e.nsPerBackgroundPixel + e.nsPerLevelPixel);
  return ns * 1e-6;
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

FallbackDecision decideEarly(const CostModel& m, const Constants& c, const FrameCounts& n) {
  return decide(m, predictFullMs(m, c, n), predictMrrFloorMs(m, c, n), true);
}

FallbackDecision decideFallback(const CostModel& m, const Constants& c, const FrameCounts& n) {
  return decide(m, predictFullMs(m, c, n), predictMrrMs(m, c, n), false);
}

}  // namespace mrr
