#include "common/cost_model.h"

#include <algorithm>

#include "common/error.h"

namespace mrr {

namespace {
double levelPixels(const LevelConstants& lc) { return static_cast<double>(lc.width) * lc.height; }
double shadeNs(const EffectCost& e, int samples) { return e.nsPerShadedPixel + e.nsPerSample * samples; }
}  // namespace

CostModel CostModel::defaults(const std::string& path) {
  CostModel m;
  // `mrr bench --calibrate FILE --paths cpu gpu --repeats 5` on the CI machine (2-core AMD EPYC
  // VM; the port on llvmpipe, LLVM 15), builtin:demo at 640×360. cpu: the mean of three runs,
  // which agreed within ~10% (2026-11-22). gpu: the median of three runs of the GPU-resident
  // port, which agreed within 5% (2026-11-23, after the one-pass blend's constants made full's
  // blend cheaper). Order: ssao, ssm, ssgi; {a, b, d, s} as EffectCost.
  if (path == "gpu") {
    m.source = "built-in default (gpu: llvmpipe on the 2-core AMD EPYC CI VM)";
    m.effect = {EffectCost{161.7, 3.30, 0.0, 1.52}, EffectCost{272.3, 1.39, 0.0, 1.55},
                EffectCost{29.2, 4.10, 21.2, 1.61}};
    m.nsPerCoarseGbufferPixel = 46.4;
    m.nsPerBlendPixel = 27.9;
    m.rasterGbuffer = true;
  } else {
    m.source = "built-in default (cpu: 2 threads on the 2-core AMD EPYC CI VM)";
    m.effect = {EffectCost{130.0, 3.40, 1.1, 1.30}, EffectCost{60.0, 0.75, 0.0, 1.45},
                EffectCost{24.0, 4.35, 13.5, 1.60}};
    m.nsPerCoarseGbufferPixel = 21.8;
    m.nsPerBlendPixel = 20.1;
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
      ec.sparseFactor = ej.at("sparse_factor").get<double>();
    }
    m.nsPerCoarseGbufferPixel = j.at("ns_per_coarse_gbuffer_pixel").get<double>();
    m.nsPerBlendPixel = j.at("ns_per_blend_pixel").get<double>();
    m.rasterGbuffer = j.value("raster_gbuffer", false);
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
                            {"sparse_factor", ec.sparseFactor}};
  }
  return {{"source", source},
          {"effects", effects},
          {"ns_per_coarse_gbuffer_pixel", nsPerCoarseGbufferPixel},
          {"ns_per_blend_pixel", nsPerBlendPixel},
          {"raster_gbuffer", rasterGbuffer}};
}

// SPEC §11: Σ_ℓ shaded (|S_ℓ|·(a + b·N)·s + P_ℓ·d) + Σ_{ℓ≥1} (P_ℓ·g + F) + W·H·β, in ms, where
// F = max(T0 − P_0·g, 0) for a rasterised G-buffer measured at T0 ms, else 0.
double predictMrrMs(const CostModel& m, const Constants& c, const std::array<long long, kLevelCount>& shaded,
                         double gbuffer0Ms) {
  const EffectCost& e = m.effect[static_cast<size_t>(c.effect)];
  const double perSceneNs =
      m.rasterGbuffer ? std::max(gbuffer0Ms * 1e6 - levelPixels(c.levels[0]) * m.nsPerCoarseGbufferPixel, 0.0) : 0.0;
  double ns = static_cast<double>(c.width) * c.height * m.nsPerBlendPixel;
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled) continue;
    if (lc.index > 0) ns += levelPixels(lc) * m.nsPerCoarseGbufferPixel + perSceneNs;
    if (lc.shaded) ns += static_cast<double>(shaded[static_cast<size_t>(lc.index)]) * shadeNs(e, c.samples()) * e.sparseFactor +
                         levelPixels(lc) * e.nsPerLevelPixel;
  }
  return ns * 1e-6;
}

// SPEC §11: W·H·(a + b·N) + P_0·d, in ms.
double predictFullMs(const CostModel& m, const Constants& c) {
  const EffectCost& e = m.effect[static_cast<size_t>(c.effect)];
  return (static_cast<double>(c.width) * c.height * shadeNs(e, c.samples()) + levelPixels(c.levels[0]) * e.nsPerLevelPixel) *
         1e-6;
}

FallbackDecision decideFallback(const CostModel& m, const Constants& c, const std::array<long long, kLevelCount>& shaded,
                                double gbuffer0Ms) {
  FallbackDecision d;
  d.evaluated = true;
  d.predictedFullMs = predictFullMs(m, c);
  d.predictedMrrMs = predictMrrMs(m, c, shaded, gbuffer0Ms);
  d.fellBack = d.predictedFullMs - d.predictedMrrMs <= 0.0;
  d.costModel = m.source;
  return d;
}

}  // namespace mrr
