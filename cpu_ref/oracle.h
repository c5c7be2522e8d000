#pragma once
// The oracle's stages as one object: each stage a function of explicit inputs, with the
// method's and the effect's dispatch written here once. Every input is a field of a FrameResult
// (`in`), named in the stage's "reads" line as common/stages.h names its part, so the same
// stage runs on any frame's images:
//  - the oracle's own frame (cpu_ref/pipeline.cpp) runs them in order on what it made;
//  - compare's same-input checks (compare/parity/) run them on the port's or a file's images;
//  - the stage bench (compare/bench/stage_bench.cpp) times them one at a time;
//  - probe and explore explain them (cpu_ref/probe.h).
// Outside cpu_ref/ this header, cpu_ref/pipeline.h (the renderer) and cpu_ref/probe.h are the
// only ones included (docs/architecture.md).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/driver.h"
#include "common/effect_budget.h"
#include "common/frame.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/foveation.h"
#include "cpu_ref/masks.h"

namespace mrr {

class RayScene;
struct OracleScratch;

class OracleStages {
 public:
  // `light`: the scene's (SSGI's direct light, the shaded image); `rays`: the scene's BVH, for
  // the stages that cast rays (the G-buffers and the shadow map), null for a caller that brings
  // those stages' images (a same-input check).
  explicit OracleStages(const DirectionalLight& light, const RayScene* rays = nullptr);
  ~OracleStages();
  OracleStages(const OracleStages&) = delete;
  OracleStages& operator=(const OracleStages&) = delete;

  // 1. The G-buffers (docs/spec.md §1). Reads: the view; rays.
  GBuffer gbuffer(const View& view, const LevelConstants& level) const;
  // A coarser level's: level 0 subsampled (reads gbuffer.L0), or with --coarse-gbuffer render
  // rays at the level's pixel centres.
  GBuffer coarseGBuffer(const FrameResult& in, int level) const;
  // The light's shadow map (§6): rays.
  ShadowMap shadowMap(const Constants& c) const;
  // The one-tap shadow test at full res. Reads: gbuffer.L0, shadowmap, view.
  ImageU8 shadowTest(const FrameResult& in) const;
  // The never-slower rule's samples (§11): what PCSS pays (reads gbuffer.L0, shadowmap, view)
  // and the edge sample (reads gbuffer.L0, shadowtest for SSM).
  ImageU8 pcfSample(const FrameResult& in) const;
  ImageU8 edgeSample(const FrameResult& in) const;

  // 2. The edge kinds and E (§2). Reads: gbuffer.L0, shadowtest (SSM).
  EdgeImages edges(const FrameResult& in) const;
  // The edge guard band: pixels whose normal or depth measure lies within `band` (relative) of
  // τ_n or τ_z, where two correct paths may decide an edge differently. Reads: gbuffer.L0.
  std::vector<char> edgeGuardBand(const FrameResult& in, float band) const;

  // 3. Which pixels of which level are shaded.
  // §13's eccentricity, motion and level limit. Reads: gbuffer.L0, view.
  LevelLimit levelLimit(const FrameResult& in) const;
  // §12's footprint of the effect at the edges. Reads: gbuffer.L0, edges, shadowmap, view.
  ImageF footprint(const FrameResult& in) const;
  // §3 step 1 and §12's widening with what they are made of (for probe's "why"). Reads: edges.
  MaskStages maskStages(const FrameResult& in, const ImageF* footprint) const;
  // The method's mask builder (its row's MaskBuilder). Reads: edges, levellimit; mrr-effect also
  // the footprint's inputs; tiles returns its rates in *tileRates.
  Masks masks(const FrameResult& in, ImageU8* tileRates = nullptr) const;
  Masks masks(const FrameResult& in, MaskBuilder builder, ImageU8* tileRates = nullptr) const;  // another builder
  Masks edgeMasks(const FrameResult& in) const;
  Masks effectMasks(const FrameResult& in, const ImageF* footprint = nullptr) const;  // footprint: made if null
  Masks tileMasks(const FrameResult& in, ImageU8& rates) const;
  Masks tileStencils(const FrameResult& in) const;  // the stencils of in's own tilerates
  // §9's tile rates, limited by §13. Reads: edges, levellimit.
  ImageU8 tileRates(const FrameResult& in) const;
  // §12.2: level ℓ's a-posteriori marks from its next coarser enabled level's result, limited
  // as M_ℓ was. Reads: sub, stencil and gbuffer.hit of that level; levellimit.
  // With SPEC §12.4's budget (in.refinement[ℓ].budgeted) the coarser pixels are marked by the
  // selection instead of τ_v alone (also reads gbuffer.L0's hit, stencil.Lℓ, the PCF sample and
  // in.refinement[ℓ]); `selection`, if given, receives it (empty without a budget).
  ImageU8 marks(const FrameResult& in, int level, RefinementSelection* selection = nullptr) const;
  // §12.2 step 2: M_ℓ ∨= marks, a_ℓ blurred again, S_ℓ ∨= [a_ℓ > 0].
  void refine(MaskLevel& level, const ImageU8& marks, const LevelConstants& lc) const;

  // 4. The effect at level ℓ's stencilled pixels (§4, §6). Reads: gbuffer.Lℓ, stencil.Lℓ,
  // shadowmap (SSM, SSGI), view. Its sub-steps (SSAO's occluder planes, SSGI's direct light)
  // are named through `stage`, and long SSAO levels report their tenths through `progress`.
  ImageF raw(const FrameResult& in, int level, const StageFn& stage = nullptr, const ProgressFn& progress = nullptr) const;
  // c_ℓ: SSAO's mask-aware bilateral blur of `raw`; the others' raw itself. Reads: stencil.Lℓ, gbuffer.Lℓ.
  ImageF sub(const FrameResult& in, int level, const ImageF& raw) const;

  // 5. Upsample and blend coarse to fine (§5), or the peers' composition (§9), by the method's
  // row. Reads: sub, stencil, alpha per level; peers also the G-buffers and tilerates.
  BlendResult blend(const FrameResult& in, bool keepStages) const;
  // The same-input form of the blend: each step on `in`'s own earlier steps (ĉ_ℓ and α_ℓ from its
  // c_ℓ, S_ℓ, a_ℓ; c'_ℓ from its ĉ_ℓ, α_ℓ and c'_coarser); the peers' composition as `blend`.
  // Levels whose blend images `in` does not hold are left empty.
  BlendResult blendStepwise(const FrameResult& in) const;

  // §14's temporal term: the previous frame's result reprojected and blended where the coarser
  // levels serve the pixel. Reads: final (the blend's), gbuffer.L0, stencil.L0, alpha.L0, view;
  // the history.
  TemporalImages temporal(const FrameResult& in, const FrameHistory& history) const;

  // 6. The shaded image for viewing (§6). Reads: gbuffer.L0, final, shadowtest, view; the light.
  ImageF shaded(const FrameResult& in) const;

 private:
  const DirectionalLight& light_;  // the scene's, read at each stage (a test may move it between frames)
  const RayScene* rays_;
  std::unique_ptr<OracleScratch> scratch_;  // per-level buffers reused from frame to frame
};

}  // namespace mrr
