#pragma once
// The oracle, end to end: scene → G-buffers → edges → masks → sub-images → blend.
// Data flows one way through these stages; FrameResult keeps every intermediate so that
// --stages, --report and probe can show them.
#include <array>
#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "common/camera.h"
#include "common/cost_model.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/blend.h"
#include "cpu_ref/edges.h"
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/masks.h"
#include "cpu_ref/shadowmap.h"
#include "cpu_ref/ssao.h"

namespace mrr {

struct LevelResult {
  GBuffer gbuffer;   // empty for disabled levels
  MaskLevel masks;   // M_ℓ, a_ℓ, S_ℓ
  ImageF raw;        // the effect before the bilateral blur
  ImageF sub;        // c_ℓ, after the bilateral blur
  int64_t shadedPixels = 0;  // |S_ℓ|
  int64_t shadedBlockPixels = 0;  // 8 × the 4×2 blocks holding any S_ℓ = 1: what llvmpipe shades
};

struct StageTiming {
  std::string stage;
  double ms = 0.0;
};

struct FrameResult {
  Constants constants;
  View view;
  DirectionalLight light;  // the scene's light, as rendered
  ShadowMap shadowMap;  // SSM and SSGI
  ImageU8 shadowLit;    // the one-tap shadow test on the full-res grid (SSM, SSGI)
  EdgeImages edges;     // on the padded full-res grid (modes mrr and tiles)
  ImageU8 tileRates;    // tiles: each 16×16 tile's level, 0 (1×1), 1 (2×2) or 2 (4×4)
  FallbackDecision fallback;  // SPEC §11, mode mrr
  std::array<LevelResult, kLevelCount> levels;
  BlendResult blend;  // ĉ_ℓ, α_ℓ, c'_ℓ, final, level map on W×H
  int64_t shadedPixelsTotal = 0;
  double idealSpeedup = 1.0;  // W·H / Σ|S_ℓ| (SPEC §4)
  // The same over whole 4×2 blocks: llvmpipe skips a block only when all eight fail the
  // stencil (PLATFORM.md), so this is the most a stencilled pass can gain there.
  double blockIdealSpeedup = 1.0;
  std::vector<StageTiming> timings;  // in pipeline order; "total" last

  ImageF shaded;      // W×H linear RGB for viewing (SPEC §6)

  const ImageF& final() const { return blend.final; }
  // What stage 5 blends: each level's c_ℓ, S_ℓ and a_ℓ (both paths' blend takes these).
  std::array<LevelImages, kLevelCount> blendInputs() const;
  // |S_ℓ| per level, their sum and the ideal speedup W·H / Σ|S_ℓ| (SPEC §4), from the stencils.
  void countShadedPixels();
  double timing(const std::string& stage) const;
};

// Receives "stage name" as each stage starts (progress lines on stderr).
using ProgressFn = std::function<void(const std::string&)>;

struct RenderOptions {
  // Keep the per-level full-res blend images (ĉ_ℓ, α_ℓ, c'_ℓ) for --stages and probe. The
  // benchmark turns it off: they are debugging output, not part of the method's cost.
  bool keepStages = true;
  ProgressFn progress;
  // The never-slower rule's per-pixel costs (SPEC §11); null: CostModel::defaults of the path.
  const CostModel* costModel = nullptr;
};

// SPEC §11 on a frame whose stencils are `masks` and nothing else of the method is paid yet:
// when f.constants.neverSlower, decides with `model` into f.fallback and, on a fallback,
// switches f.constants and `masks` to a full-res frame. Both pipelines call it at that point.
// `gbuffer0Ms`: the frame's level-0 G-buffer time, for a model with a rasterised G-buffer (the
// port, on a warm renderer); 0 leaves the per-scene term out.
void applyNeverSlower(FrameResult& f, std::array<MaskLevel, kLevelCount>& masks, const CostModel& model,
                      double gbuffer0Ms = 0.0);

// The per-level |S_ℓ| of a set of stencils (0 for levels that are not shaded).
std::array<long long, kLevelCount> shadedPixelCounts(const std::array<MaskLevel, kLevelCount>& masks,
                                                     const Constants& constants);

// The bytes one rendered FrameResult holds (every level's G-buffer, masks, raw and blurred
// sub-images and per-effect scratch; the full-res edges, blend, level map and shaded image;
// the shadow map), plus the full-res images written out. An estimate made from the sizes
// alone, before anything is allocated: the memory check up front (common/memory.h).
int64_t estimateFrameBytes(const Constants& constants, bool keepStages);

class Renderer {
 public:
  explicit Renderer(const Scene& scene);  // builds the BVH
  FrameResult render(const Camera& camera, const Constants& constants, const RenderOptions& options = {}) const;
  const Scene& scene() const { return scene_; }
  double bvhBuildMs() const { return bvhBuildMs_; }

 private:
  const Scene& scene_;
  double bvhBuildMs_ = 0.0;
  std::chrono::steady_clock::time_point buildStart_ = std::chrono::steady_clock::now();
  RayScene rays_;  // built after buildStart_ is taken (member order), timed in the constructor
  // Scratch reused across frames, so a steady stream of frames does not page-fault it in
  // again each time (render() is therefore not re-entrant).
  mutable std::array<OccluderPlanes, kLevelCount> planes_;
};

}  // namespace mrr
