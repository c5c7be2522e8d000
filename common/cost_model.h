#pragma once
// The never-slower rule (SPEC §11, docs/spec.md §11). Once the stencils are known, and before
// anything is shaded, the method predicts the rest of its frame and the rest of a `full`
// frame from per-pixel costs, and shades the frame at full resolution when it predicts no
// gain. The costs are measured, not guessed: `mrr bench --calibrate` measures them on the
// machine at hand, for each path, and writes the JSON `--cost-model` reads; the defaults
// below are that command's output on this project's CI machine (docs/figures.md).
#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "common/params.h"

namespace mrr {

struct EffectCost {
  double nsPerShadedPixel = 0.0;  // a: per stencilled pixel, whatever the sample count
  double nsPerSample = 0.0;       // b: per stencilled pixel and sample
  double nsPerLevelPixel = 0.0;   // d: per pixel of every shaded level, stencilled or not
                                  //    (SSAO's occluder planes, SSGI's direct light)
  // s: a stencilled pixel of the method costs s × a pixel of a dense full frame. The pixels
  // the method shades finely sit at edges, where samples find occluders and branches
  // mispredict, and a sparse stencil is walked less efficiently: measured in mrr frames.
  double sparseFactor = 1.0;
};

struct CostModel {
  std::string source;                  // where the figures came from (shown in the report)
  std::array<EffectCost, 3> effect{};  // by Effect
  double nsPerCoarseGbufferPixel = 0.0;  // one level-ℓ G-buffer pixel, ℓ ≥ 1
  double nsPerBlendPixel = 0.0;          // the blend, per full-res pixel
  // A rasterised G-buffer (the port) also costs a part per scene, not per pixel (its triangles),
  // at every level: taken from the frame's own level-0 G-buffer time, T0 − P_0·g, added per
  // coarse level (the port passes T0 on warm frames only). Ray casting (the oracle) has none, and its decision stays a function of the
  // stencils alone (deterministic).
  bool rasterGbuffer = false;

  // The defaults, measured on this project's CI machine for the path ("cpu" or "gpu").
  static CostModel defaults(const std::string& path);
  static CostModel fromJson(const nlohmann::json& j);  // throws MrrError naming the missing key
  nlohmann::json toJson() const;
};

// What the rule decided for one frame (the report's `never_slower`).
struct FallbackDecision {
  bool evaluated = false;       // mode mrr with the rule on
  bool fellBack = false;        // the frame was shaded at full resolution
  double predictedFullMs = 0.0;      // the rest of a `full` frame: every pixel shaded
  double predictedMrrMs = 0.0;  // the rest of this frame: coarse G-buffers, Σ|S_ℓ|, blend
  std::string costModel;        // CostModel::source
};

// The remaining cost of shading `shadedPixels[ℓ]` pixels per level, plus the coarse
// G-buffers and the blend (SPEC §11); and of shading all W·H pixels at level 0.
// `gbuffer0Ms`: the frame's measured level-0 G-buffer time (read with rasterGbuffer; 0: none).
double predictMrrMs(const CostModel& model, const Constants& constants,
                         const std::array<long long, kLevelCount>& shadedPixels, double gbuffer0Ms = 0.0);
double predictFullMs(const CostModel& model, const Constants& constants);

// The rule: falls back when the predicted gain, full − multires, is ≤ 0.
FallbackDecision decideFallback(const CostModel& model, const Constants& constants,
                                const std::array<long long, kLevelCount>& shadedPixels, double gbuffer0Ms = 0.0);

}  // namespace mrr
