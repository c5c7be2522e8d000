#include "common/driver.h"

#include <algorithm>
#include <chrono>
#include <utility>

#include "common/cost_model.h"
#include "common/effect_budget.h"
#include "common/error.h"
#include "common/stages.h"

namespace mrr {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }
}  // namespace

void FrameBackend::timeStage(FrameResult& f, const std::string& name, const std::function<void()>& body) {
  const auto t0 = Clock::now();
  body();
  f.timings.push_back({name, msSince(t0)});
}

FrameMasks FrameBackend::fullMasks(FrameResult& f) { return fullModeMasks(f.constants); }
FrameMasks FrameBackend::uniformMasks(FrameResult& f) { return mrr::uniformMasks(f.constants); }

void FrameBackend::countEarly(FrameResult& f, const std::function<bool(const FrameCounts&)>& wantSample) {
  ImageU8 silhouetteBlocks;
  countHits(f.counts, fullResHit(f), f.pcfSample, f.constants, &silhouetteBlocks);
  if (!wantSample || !wantSample(f.counts)) return;
  sampleEdges(f);
  f.edgeSampled = true;
  countEdgeSample(f.counts, f.edgeSample, silhouetteBlocks, fullResHit(f), f.constants);
}

void FrameBackend::countStencils(FrameResult& f, const FrameMasks& masks) {
  countForRule(f.counts, masks.host, f.constants, fullResHit(f), f.pcfSample);
}

void FrameBackend::countHitPixels(FrameResult& f, FrameCounts* finalStencils) {
  f.countHitPixels(fullResHit(f));
  if (!finalStencils) return;
  Masks stencils;
  for (size_t l = 0; l < kLevelCount; ++l) stencils[l].stencil = f.levels[l].masks.stencil;
  countForRule(*finalStencils, stencils, f.constants, fullResHit(f), f.pcfSample);
}

FrameMasks buildMasks(FrameBackend& b, MaskBuilder builder, FrameResult& f) {
  using Build = FrameMasks (FrameBackend::*)(FrameResult&);
  // In MaskBuilder's order.
  static constexpr Build kBuilders[] = {&FrameBackend::fullMasks, &FrameBackend::uniformMasks, &FrameBackend::tileMasks,
                                        &FrameBackend::edgeMasks, &FrameBackend::effectMasks};
  static_assert(std::size(kBuilders) == static_cast<size_t>(MaskBuilder::EffectEdges) + 1);
  return (b.*kBuilders[static_cast<size_t>(builder)])(f);
}

void FrameBackend::refineMasks(FrameResult& /*f*/, int /*level*/) {
  throw MrrError(std::string("mrr-effect's a-posteriori term: the ") + pathName() + " path does not implement it");
}

void FrameBackend::temporal(FrameResult& /*f*/, const FrameHistory* /*history*/) {
  throw MrrError(std::string("the temporal term (docs/spec.md §14): the ") + pathName() + " path does not implement it");
}

FrameResult renderFrame(FrameBackend& b, const DirectionalLight& light, const Camera& camera,
                        const Constants& constants, const RenderOptions& options) {
  FrameResult f;
  f.constants = constants;
  const Constants& c = f.constants;  // what every stage reads; the never-slower rule may change it
  const MethodInfo& method = methodInfo(c.mode);  // its row (common/methods.h)
  f.camera = camera;
  f.view = makeView(camera, c.width, c.height, c.paddedWidth, c.paddedHeight);
  f.light = light;
  const auto frameStart = Clock::now();
  const StageFn stage = [&](const std::string& name, const std::function<void()>& body) {
    if (options.progress) options.progress(name);
    b.timeStage(f, name, body);
  };

  // 1. The full-res G-buffer (SPEC §1): the masks are made from it alone.
  stage(stageName(Part::GBuffer, 0), [&] { b.gbuffer(f); });

  // The light's shadow map, and its one-tap test at full res (SPEC §2 shadow edges, §6).
  if (c.needsShadowMap()) {
    stage(stageName(Part::ShadowMap), [&] { b.shadowMap(f); });
    stage(stageName(Part::ShadowTest), [&] { b.shadowTest(f); });
  }

  // SPEC §11, early: when even the least the method could still pay is no gain, the frame
  // falls back before its edges and masks.
  const CostModel model = options.costModel ? *options.costModel : CostModel::defaults(b.pathName());
  // The rule's own work is its stage, Timed::Rule (twice: these counts, then the stencils'), in the
  // method's rest of frame (SPEC §11's ρ). SSM: what PCSS pays (nothing, the search, or the search
  // and PCF), asked of one pixel in 8×8, when the model prices PCF (e > 0) and the rule will
  // decide (or the caller reads its counts). Then H, H_a, H_p and B_ℓ. Then the edge sample and its
  // reach R_ℓ, whenever the rule decides (or the caller reads its counts), unless the floor,
  // which needs no sample, already rules the method out.
  bool fellBackEarly = false;
  if (method.neverSlower)
    stage(timedName(Timed::Rule), [&] {
      const bool counted = c.neverSlower || options.sampleWithRuleOff;
      if (c.effect == Effect::Ssm && counted && model.effect[static_cast<size_t>(Effect::Ssm)].nsPerPcfSample > 0.0)
        b.samplePcf(f);
      // the edge sample, unless the floor (on these counts) already rules the method out
      const auto wantSample = [&](const FrameCounts& counts) {
        const bool floorRulesOut = c.neverSlower && decideOnFloor(model, c, counts).fellBack;
        return !floorRulesOut || options.sampleWithRuleOff;
      };
      b.countEarly(f, counted ? std::function<bool(const FrameCounts&)>(wantSample) : nullptr);
    });
  if (c.neverSlower) {
    const FallbackDecision early = decideEarly(model, c, f.counts);
    if (early.fellBack) {
      f.fallback = early;
      f.constants.fallBackToFull();
      fellBackEarly = true;
    }
  }

  // 2–3. Which pixels of which level are shaded (SPEC §2–3; the peers' §9): the edges where the
  // method finds them, then its mask builder (common/methods.h), on the backend's own objects.
  const MethodInfo& shading = fellBackEarly ? methodInfo(Mode::Full) : method;
  if (shading.findsEdges) stage(stageName(Part::Edges), [&] { b.edges(f); });
  FrameMasks masks;
  if (shading.hostMadeMasks())
    masks = buildMasks(b, shading.masks, f);
  else
    stage(stageName(Part::Stencil), [&] { masks = buildMasks(b, shading.masks, f); });
  // A caller's own masks (RenderOptions::replaceMasks: the Python module's, on the oracle's host images).
  if (options.replaceMasks && !fellBackEarly) {
    require(!masks.device, "a caller's own masks need the oracle's host masks (--path cpu)");
    options.replaceMasks(f, masks.host);
  }
  // SPEC §11: with the stencils known and nothing shaded yet, predict both frames' rest; a
  // fallback shades full's stencils, made by the same backend.
  if (method.neverSlower && !fellBackEarly) {
    stage(timedName(Timed::Rule), [&] { b.countStencils(f, masks); });
    if (applyNeverSlower(f, model)) masks = buildMasks(b, MaskBuilder::Full, f);
  }
  b.useMasks(f, masks, stage);
  for (int l = 0; l < kLevelCount; ++l)
    f.levels[static_cast<size_t>(l)].masks = std::move(masks.host[static_cast<size_t>(l)]);
  b.countShaded(f);

  // 1, continued. The coarser levels' G-buffers: level 0 at the pixels theirs hold.
  for (int l = 1; l < kLevelCount; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled)
      stage(stageName(Part::GBuffer, l), [&] { b.subsampleGBuffer(f, l); });

  // 4. Sub-images: the effect at stencilled pixels only, then SSAO's bilateral blur (SPEC §4).
  // mrr-effect's a-posteriori term (SPEC §12.2): coarse to fine, each finer level's masks
  // refined from the result of the level just shaded, then shaded.
  const bool posterior = method.aPosteriori && c.effectMask.refines() && !f.fallback.fellBack;
  if (posterior) {
    // SPEC §12.4: with a budget, what the a-priori stencils leave of B × full's predicted rest,
    // shared among the levels still to refine (what one leaves, the next may spend).
    const auto refined = [&](int l) {
      return c.levels[static_cast<size_t>(l)].enabled && l != c.coarsestEnabled && l >= c.effectMask.posteriorFinest;
    };
    // The frame's budget in whole units (the first refined level's to start from; each finer one
    // starts from what the one before it left, on the backend: the port's stays on the GPU).
    const bool budgeted = c.effectMask.budget > 0.0f;
    const double unitNs = budgeted ? budgetUnitNs(predictFullMs(model, c, f.counts) * 1e6) : 0.0;
    int after = -1;
    for (int l = kLevelCount - 1; l >= 0; --l) {
      if (!c.levels[static_cast<size_t>(l)].enabled) continue;
      if (refined(l)) {
        RefinementRecord& r = f.refinement[static_cast<size_t>(l)];
        if (budgeted) {
          int levelsLeft = 0;
          for (int k = l; k >= 0; --k) levelsLeft += refined(k) ? 1 : 0;
          r.budgeted = true;
          r.levelsLeft = levelsLeft;
          r.after = after;
          r.unitNs = unitNs;
          r.prices = refinementPrices(model, c, l, f.counts);
          r.units = unitPrices(r.prices, unitNs);
          if (after < 0) r.leftUnits = budgetUnits(refinementBudgetNs(model, c, f.counts), unitNs);
          // SPEC §14.2: what the previous frame selected here, for the marks' hysteresis
          if (c.effectMask.hysteresis > 0.0f && options.history)
            r.previousMarked = options.history->marked[static_cast<size_t>(l)];
          after = l;
        }
        stage(stageName(Part::Stencil), [&] { b.refineMasks(f, l); });
      }
      b.shadeLevel(f, l, stage);
    }
    b.countShaded(f);
  } else {
    for (int l = 0; l < kLevelCount; ++l)
      if (c.levels[static_cast<size_t>(l)].enabled) b.shadeLevel(f, l, stage);
  }

  // 5. Upsample and blend, coarse to fine (SPEC §5); the peers compose their own way (§9).
  stage(stageName(Part::Final), [&] { b.blend(f); });
  // SPEC §14: the temporal term, from the previous frame where there is one; the history for the next.
  if (c.temporal.on()) stage(stageName(Part::Temporal), [&] { b.temporal(f, options.history); });
  // 6. The shaded image for viewing (SPEC §6).
  stage(stageName(Part::Shaded), [&] { b.shade(f); });
  b.endFrame(f);
  f.timings.push_back({timedName(Timed::Total), msSince(frameStart)});
  // Figures for reports, after the clock stopped: H and the ideal speedups, and (SPEC §12.4) each
  // level's predicted time on its final stencils beside the measured
  const bool predictLevels = method.neverSlower && !fellBackEarly;
  FrameCounts finalCounts = f.counts;
  b.countHitPixels(f, predictLevels ? &finalCounts : nullptr);
  if (predictLevels)
    for (int l = 0; l < kLevelCount; ++l)
      f.predictedLevelMs[static_cast<size_t>(l)] = predictLevelMs(model, f.constants, finalCounts, l);
  return f;
}

}  // namespace mrr
