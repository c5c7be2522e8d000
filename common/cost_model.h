#pragma once
// The never-slower rule (SPEC §11, docs/spec.md §11). The method predicts the rest of its
// frame and the rest of a `full` frame from what it knows of the frame, and shades the frame at
// full resolution when it predicts no gain. It decides twice:
//  - early, after the level-0 G-buffer (and the shadow map), from the frame's size, its pixels
//    on geometry and its silhouettes: when even the least the method could pay (edges, masks,
//    coarse G-buffers, blend, its silhouettes at every level, every pixel at the coarsest
//    level) is no less than full's rest, the frame falls back before the edges are found (and
//    before the edge sample, which the floor does not need); past the floor, from the edge
//    sample's estimate of the stencils, when going on costs no less than full's rest;
//  - then, once the stencils are known and before anything is shaded, from |S_ℓ| and how many
//    of those pixels lie on geometry.
// Background pixels cost each mode what they cost (the effects leave them at once), the
// coarse G-buffers cost a copy of their pixels (level 0 subsampled, SPEC §1), and the effect
// costs per pixel and per sample. The costs are measured, not guessed:
// `mrr bench --calibrate` fits them on the machine at hand, for each path, and writes the JSON
// `--cost-model` reads; the defaults, common/cost_models/cpu.json and gpu.json (compiled in),
// are that command's output on this project's CI machine (docs/figures.md). Every input is a
// count, never a clock: the oracle's decision, and so its image, is the same on every run and
// any thread count.
#include <array>
#include <cstdint>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "common/params.h"

namespace mrr {

// SPEC §11: s_ℓ = 1 + (s − 1)(1 − q_ℓ) prices a level by its stencil's coverage only for s in
// [1, 2]: below 1 a stencilled pixel would cost less than a dense one, past 2 a level would cost
// less as its stencil grew. The calibration holds s there and --cost-model refuses others.
inline constexpr double kMinSparseFactor = 1.0, kMaxSparseFactor = 2.0;
// η_ℓ (CostModel::edgeBandFill) unpriced: the early estimate takes φ_ℓ |R_ℓ| alone.
inline constexpr double kNoEdgeBand = std::numeric_limits<double>::infinity();

struct EffectCost {
  double nsPerShadedPixel = 0.0;      // a: per shaded pixel on geometry, whatever the sample count
  double nsPerSample = 0.0;           // b: per shaded pixel on geometry and sample
  double nsPerLevelPixel = 0.0;       // d: per pixel on geometry of every shaded level (SSAO's
                                      //    occluder planes, SSGI's direct light)
  double nsPerBackgroundPixel = 0.0;  // c: per shaded pixel off geometry (the effect's early out)
  // e: more per sample where the pixel pays PCF (SSM: PCSS filters only where its blocker
  // search finds blockers; any other pixel pays the search alone, or less).
  double nsPerPcfSample = 0.0;
  // s: a stencilled pixel of the method costs s × a pixel of a dense full frame, s in
  // [kMinSparseFactor, kMaxSparseFactor] (SPEC §11's s_ℓ). The pixels
  // the method shades finely sit at edges, where samples find occluders and branches
  // mispredict, and a sparse stencil is walked less efficiently: measured in mrr frames.
  double sparseFactor = 1.0;
  // k: the method's frame beyond what it pays per pixel, in ms whatever its
  // size: the set-up of its extra passes (a draw call, a framebuffer switch and a drain of the
  // rasteriser per pass on the port; a parallel loop's start on the oracle). It decides small
  // frames on the port.
  double fixedMs = 0.0;
  // k₀: the same for a full frame's shading (its passes' set-up; on llvmpipe SSM's pass alone
  // costs ~10 ms whatever its size).
  double fullFixedMs = 0.0;
  // ρ: the rule's own work per full-res pixel (its stage "rule": H, H_a, H_p and B_ℓ counted from
  // the hit flags, which the port reads back, SSM's PCF sample, then the stencils' counts). The
  // method pays it whichever way the rule decides; full does not.
  double nsPerRulePixel = 0.0;
  // ν: more per searching pixel and texel of its map footprint (SSM: neighbouring searches that
  // land f texels apart share fewer of the map's cache lines; measured on the plane, the memory
  // part of a search halves as the frame's side doubles, docs/figures.md). A level-ℓ pixel's
  // footprint is s_ℓ f̄, at most kMaxFootprintTexels: footprintTexels.
  double nsPerFootprintTexel = 0.0;
};

struct CostModel {
  std::string source;                  // where the figures came from (shown in the report)
  std::array<EffectCost, 3> effect{};  // by Effect
  // g: one level-ℓ G-buffer pixel, ℓ ≥ 1: a copy of a level-0 pixel (SPEC §1), whatever the
  // scene (no ray, no triangle).
  double nsPerCoarseGbufferPixel = 0.0;
  double nsPerFullBlendPixel = 0.0;  // β₀: full's blend (level 0 copied into the result), per pixel
  double nsPerBlendPixel = 0.0;      // β: the method's blend beyond β₀, per full-res pixel
  // β_f: more per full-res pixel where a finer level can show (|S_j| s_j², j the coarsest
  // enabled level below the coarsest k: finerLevelsArea): the blend upsamples a finer level only
  // there, on both paths, so its cost grows with the area the finer levels cover.
  double nsPerFineBlendPixel = 0.0;
  double nsPerEdgePixel = 0.0;      // ε: edges, per padded full-res pixel (the early decision's)
  double nsPerEdgeHitPixel = 0.0;   // ε_h: more per full-res pixel on geometry (a miss leaves at once)
  double nsPerMaskPixel = 0.0;      // μ: the masks, per padded full-res pixel (the same)
  // μ_A: more per pixel of the edge sample's reach, A = Σ_{ℓ<k} |R_ℓ| (level-ℓ pixels): the port
  // draws its blur passes only near edges, so its masks cost what the edges' surroundings cover.
  double nsPerMaskReachPixel = 0.0;
  double edgesMasksFixedMs = 0.0;  // κ: the edges' and masks' passes per frame, whatever its size
  // μ_e: mrr-effect's masks beyond mrr's (SPEC §12: the footprint, its pyramid and the widening
  // of each level), per padded full-res pixel. Paid with the masks, before the stencils are known:
  // the early decision's and the floor's.
  double nsPerEffectMaskPixel = 0.0;
  // μ_v: the a-posteriori term (SPEC §12.2, mrr-effect with τ_v > 0: the oracle's), per level pixel
  // of each level it refines (the range test, the marks, the blur again and the stencil). Paid
  // after the decision, whatever the stencils: the method's rest and its floor.
  double nsPerRefinePixel = 0.0;
  // φ_ℓ, ℓ < 3: the most of the edge sample's reach the stencil fills, |S_ℓ| / |R_ℓ| where edges
  // crowd (their bands overlap and fill the blocks between them).
  std::array<double, kLevelCount - 1> stencilFill{};
  // η_ℓ, ℓ < 3: |S_ℓ| per sampled edge block, in the block's level-ℓ pixels ((8 / s_ℓ)²), where
  // edges are sparse: an edge crosses a block, and S_ℓ is a band around it whatever the reach
  // about it (measured: |S_0| ≈ 64 |Ê| on every sweep frame, |S_0| / |R_0| from 0.29 to 1). The early
  // estimate's |S_ℓ| = min(φ_ℓ |R_ℓ|, η_ℓ |Ê| (8 / s_ℓ)²): estimateStencilPixels. Infinite: no band,
  // φ_ℓ |R_ℓ| alone.
  std::array<double, kLevelCount - 1> edgeBandFill{kNoEdgeBand, kNoEdgeBand, kNoEdgeBand};
  // w: how far the early estimate of the method's rest, R̂, is from the one its stencils give: R
  // is taken as uniform on R̂ (1 ± w) (√3 × the calibration frames' RMS relative difference).
  double estimateSpread = 0.0;

  // The defaults, measured on this project's CI machine for the path ("cpu" or "gpu"):
  // common/cost_models/<path>.json, compiled in. Throws MrrError for another path.
  static CostModel defaults(const std::string& path);
  // Throws MrrError naming `origin` (the file, or the option) and the missing or bad key.
  static CostModel fromJson(const nlohmann::json& j, const std::string& origin = "a cost model");
  // A JSON file `mrr bench --calibrate` wrote (`--cost-model FILE`): throws MrrError on a file it
  // cannot read, that is not a JSON object, or that fromJson refuses.
  static CostModel fromFile(const std::string& file);
  nlohmann::json toJson() const;
};

// What the rule knows of a frame: counts only.
struct FrameCounts {
  int64_t hitPixels = 0;  // H: level-0 pixels (W×H) on geometry
  // H_a: of those, the ones paying the effect's per-pixel cost (a, b): all of them but for SSM
  // with e > 0, whose pixels facing away from the light return before any tap. H_p: of those,
  // paying PCF (SSM with e > 0; else 0). Both estimated from one pixel in 8×8 (pcfSample).
  int64_t searchedPixels = 0;
  int64_t pcfPixels = 0;
  // F: Σ over H_a of the map footprint (SSM; the sample's, in steps of 1/kFootprintSteps texel; 0
  // without a sample): F / (kFootprintSteps H_a) is the frame's mean footprint f̄ in texels.
  int64_t searchedFootprint = 0;
  // B_ℓ: level-ℓ pixels whose block holds a silhouette pixel (a full-res pixel on geometry with a
  // background 4-neighbour: a background edge, SPEC §2). B_0 ⊆ E ⊆ S_0, and the masks' closure
  // puts maxpool(B_0) into every coarser enabled S_ℓ, so the method shades at least B_ℓ at every
  // level whatever else its edges find: the early floor counts them (countHits).
  std::array<int64_t, kLevelCount> silhouette{};
  // |S_ℓ| and |S_ℓ ∩ hit| per level (a level-ℓ pixel on geometry when its full-res pixel
  // (x·s + s/2, y·s + s/2) is: levelPixelHits). Zero before the stencils are known.
  std::array<int64_t, kLevelCount> shaded{}, shadedHit{};
  std::array<int64_t, kLevelCount> shadedSearched{};  // |S_ℓ ∩ hit ∩ searched|
  std::array<int64_t, kLevelCount> shadedPcf{};       // |S_ℓ ∩ hit ∩ pcf| (SSM)
  // The edge sample (countEdgeSample): |Ê|, the 8×8 blocks whose diagonal holds an edge (or
  // that hold a silhouette pixel); R_ℓ, the level-ℓ pixels of the blocks within r_ℓ of one (or of a finer level's R), for
  // ℓ below the coarsest; and the full-res pixels on geometry in R_ℓ's blocks. What the early
  // decision estimates S_ℓ and the masks' cost from.
  int64_t edgeBlocks = 0;
  std::array<int64_t, kLevelCount> reach{}, reachHits{};
};

// What the rule decided for one frame (the report's `never_slower`).
struct FallbackDecision {
  bool evaluated = false;        // mode mrr with the rule on
  bool fellBack = false;         // the frame was shaded at full resolution
  bool wouldFallBack = false;    // with the rule off: what it would have decided on the stencils
  bool early = false;            // decided before the edges (fellBack then: no edges, no masks)
  bool onFloor = false;          // fell back early on the floor alone, before the edge sample (not taken)
  double predictedFullMs = 0.0;  // the rest of a `full` frame
  // the rest of this frame (early: the larger of the least it could be and the edge sample's
  // estimate, edges and masks included)
  double predictedMrrMs = 0.0;
  std::string costModel;         // CostModel::source
};

// n_j s_j², j the coarsest enabled level below the coarsest k: the full-res pixels under its n_j
// level pixels. With n = |S_ℓ| that is where any finer level can show in the blend (the closure
// puts every finer level's blocks into S_j), and so where the blend does more than copy level k
// (SPEC §11's β_f; a sum over the levels counted a pixel once per level, where the blend stops at
// the first level whose α is 1).
double finerLevelsArea(const Constants& constants, const std::array<int64_t, kLevelCount>& perLevel);

// SPEC §11: f_ℓ = min(s_ℓ f̄, kMaxFootprintTexels), f̄ = F / (kFootprintSteps H_a): the map
// footprint of a searching level-ℓ pixel, in texels (0 without a sample).
double footprintTexels(const LevelConstants& level, const FrameCounts& counts);
// SPEC §11, in ms. Full's rest: H_a (a + b N + ν f_0) + H_p e N + (W·H − H_a) c + P_0 d + k₀.
double predictFullMs(const CostModel& model, const Constants& constants, const FrameCounts& counts);
// The method's rest once its stencils are known: Σ_ℓ shaded ((|S_ℓ ∩ searched| (a + b N + ν f_ℓ) +
// |S_ℓ ∩ pcf| e N) s + |S_ℓ \ searched| c + P_ℓ d) + Σ_{ℓ≥1 enabled} P_ℓ g + W·H (β₀ + β)
// + |S_j| s_j² β_f + W·H ρ + Σ_{ℓ refined} P_ℓ μ_v (mrr-effect's a-posteriori term) + k.
double predictMrrMs(const CostModel& model, const Constants& constants, const FrameCounts& counts);
// The least the method can still pay before its edges: P_0 (ε + μ (+ μ_e)) + H ε_h + κ + Σ_{ℓ refined} P_ℓ μ_v + the coarse G-buffers
// and the blend as above (B_j for |S_j|) + W·H ρ + d over every shaded level + its silhouettes B_ℓ
// shaded at every level but the coarsest + every pixel of the coarsest enabled level, paying in
// proportion to H_a and H_p, + k.
double predictMrrFloorMs(const CostModel& model, const Constants& constants, const FrameCounts& counts);

// SPEC §11: |Ŝ_ℓ| = max(B_ℓ, min(φ |R_ℓ|, η |Ê| (8 / s_ℓ)²)), level-ℓ pixels, for ℓ below the
// coarsest: the stencil the edge sample predicts, with fill φ and band η (CostModel's φ_ℓ, η_ℓ).
double estimateStencilPixels(double fill, double bandFill, const LevelConstants& level, const FrameCounts& counts);
// S_ℓ as the edge sample sees it, before the edges (counts.shaded… unknown): for ℓ below the
// coarsest k, |S_ℓ| = estimateStencilPixels, on geometry in the share R_ℓ's blocks are, paying
// (H_a, H_p) in the frame's shares of H; all of level k, in the frame's shares.
FrameCounts estimateStencils(const CostModel& model, const Constants& constants, const FrameCounts& counts);
// SPEC §11: P_0 μ_e for mode mrr-effect (its masks' footprint and widening), else 0; in ns.
double effectMaskNs(const CostModel& model, const Constants& constants);
// SPEC §11: Σ_{ℓ refined} P_ℓ μ_v for mrr-effect's a-posteriori term (τ_v > 0: every enabled level
// ℓ ≥ ℓ_v but the coarsest), else 0; in ns.
double refineNs(const CostModel& model, const Constants& constants);
// The edges and the masks, from the edge sample's reach A = Σ R_ℓ: P_0 (ε + μ) + H ε_h + A μ_A
// (+ P_0 μ_e for mrr-effect) + κ.
double predictEdgesMasksMs(const CostModel& model, const Constants& constants, const FrameCounts& counts);
// The method's whole frame after the early decision, estimated from the edge sample: the edges
// and the masks and R̂, predictMrrMs on estimateStencils' counts.
double predictMrrEstimateMs(const CostModel& model, const Constants& constants, const FrameCounts& counts);
// What going on from the early decision costs: the edges and masks, then the cheaper of the
// method's rest R and full's F, decided on the stencils: E[min(R, F)] with R uniform on
// R̂ (1 ± w). Where the edges and masks are cheap and R̂ near F, going on to decide on the
// stencils is worth its price; where they are dear, it is not.
double predictContinuingMs(const CostModel& model, const Constants& constants, const FrameCounts& counts,
                           double fullMs);

// The rule, early (counts.shaded unknown) and with the stencils: falls back when the predicted
// gain, full − multires, is ≤ 0. On the floor alone first (countHits' counts: no edge sample
// needed), so a frame the floor already rules out skips the sample; decideEarly returns that
// decision when it falls back, else max(floor, continuing) against full.
FallbackDecision decideOnFloor(const CostModel& model, const Constants& constants, const FrameCounts& counts);
FallbackDecision decideEarly(const CostModel& model, const Constants& constants, const FrameCounts& counts);
FallbackDecision decideFallback(const CostModel& model, const Constants& constants, const FrameCounts& counts);

// ---- SPEC §12.4: mrr-effect's a-posteriori term with a budget in predicted time -------------

// What one more level-ℓ pixel costs, by its class, in ns (SPEC §11): paying the effect
// (s'_ℓ (a + b N + ν f_ℓ)), paying PCF too (+ s'_ℓ e N), or leaving at once (c: off geometry, or SSM
// facing away). s'_ℓ = 1 + (s − 1)(1 − 2 q_ℓ) is the marginal of §11's s_ℓ-priced level at its
// coverage q_ℓ: the next pixel a stencil takes costs less than the first.
struct PixelPrices {
  double paying = 0.0, pcf = 0.0, leaving = 0.0;
};
// The same in the budget's whole units (common/effect_budget.h unitPrices), which both paths add
// exactly.
struct UnitPrices {
  uint32_t paying = 0, pcf = 0, leaving = 0;
};
PixelPrices refinementPrices(const CostModel& model, const Constants& constants, int level, const FrameCounts& counts);

// The budget of the frame, in ns: B × full's predicted rest less the method's predicted rest on
// its a-priori stencils (SPEC §11's predictFullMs and predictMrrMs on f.counts, which
// countForRule filled), never below 0.
double refinementBudgetNs(const CostModel& model, const Constants& constants, const FrameCounts& counts);

// SPEC §12.4's per-level figures for the report: a shaded level's predicted time on its final
// stencil (§11's terms for that level alone: its shaded pixels priced with s_ℓ, and d over the
// level), ms.
double predictLevelMs(const CostModel& model, const Constants& constants, const FrameCounts& counts, int level);

}  // namespace mrr
