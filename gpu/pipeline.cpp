#include "gpu/pipeline.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <chrono>
#include <optional>
#include <utility>
#include <vector>

#include "common/cost_model.h"
#include "common/driver.h"
#include "common/effect_budget.h"
#include "common/error.h"
#include "common/stages.h"
#include "gpu/bilateral.h"
#include "gpu/blend.h"
#include "gpu/counts.h"
#include "gpu/edges.h"
#include "gpu/effect_masks.h"
#include "gpu/gbuffer.h"
#include "gpu/masks.h"
#include "gpu/pass_clock.h"
#include "gpu/peers.h"
#include "gpu/program.h"
#include "gpu/rule.h"
#include "gpu/shade.h"
#include "gpu/shadowmap.h"
#include "gpu/ssao.h"
#include "gpu/ssgi.h"
#include "gpu/ssm.h"
#include "gpu/stencil.h"
#include "gpu/temporal.h"
#include "gpu/traffic.h"

namespace mrr::gpu {

bool isPortOnlyStage(const std::string& stage) {
  const std::optional<TimedStage> t = findTimed(stage);
  return t && t->info().on == TimedOn::Port;
}

GpuTiming parseGpuTiming(const std::string& name) {
  if (name == "auto") return GpuTiming::Auto;
  if (name == "wall") return GpuTiming::Wall;
  if (name == "query") return GpuTiming::Query;
  if (name == "passes") return GpuTiming::Passes;
  throw MrrError("--gpu-timing " + name + ": unknown timing (expected auto, wall, query or passes)");
}

GpuRenderer::GpuRenderer(const Scene& scene, int deviceIndex, GpuTiming timing)
    : scene_(scene), context_(deviceIndex), gpuScene_(scene),
      timerQueries_(usesTimerQueries(timing, context_.renderer())), passTiming_(timing == GpuTiming::Passes) {}

bool usesTimerQueries(GpuTiming timing, const std::string& renderer) {
  const bool software =
      renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
  return timing == GpuTiming::Query || (timing == GpuTiming::Auto && !software);
}

std::string GpuRenderer::timingMethod() const {
  if (passTiming_)
    return "glFinish + wall clock around each stage and around each draw (--gpu-timing passes, a diagnostic: the "
           "waits serialise the frame; the report's passes give each program's draws per stage)";
  if (timerQueries_)
    return "GL_TIME_ELAPSED queries around each stage's GL work (no glFinish between stages); total on the wall "
           "clock";
  return "glFinish + wall clock around each stage (timer queries are wrong on llvmpipe); with --stages or probe every "
         "stage is read back inside its timing, else nothing is (the frame is GPU-resident: the report's gl object)";
}

namespace {
// The port's side of the frame contract (common/driver.h). Every stage's images stay on the GPU
// (docs/port.md, "The GPU-resident frame"): the masks are the port's own targets (MaskTargets,
// handed on as the frame's DeviceMasks), where they hold work is known on the GPU alone (block
// maps, gpu/blocks.h), and the never-slower rule's counts are summed there (gpu/rule.h) and read
// as a few integers. What the caller asked for (RenderOptions::outputs) is read back after the
// clock has stopped (readOutputs). With keepStages (--stages, probe, compare) every stage is
// read back too, inside its timing, into the structures the oracle fills.
class PortFrame final : public FrameBackend {
 public:
  PortFrame(const GpuScene& scene, const Scene& source, bool timerQueries, bool passTiming, const RenderOptions& options)
      : scene_(scene), source_(source), timerQueries_(timerQueries), keep_(options.keepStages),
        outputs_(options.outputs), start_(processTraffic()) {
    if (passTiming) passClock_.emplace();
  }

  const char* pathName() const override { return "gpu"; }

  void timeStage(FrameResult& f, const std::string& name, const std::function<void()>& body) override {
    if (timerQueries_) {  // one query per stage, read once the frame is done (timings[index] ← query)
      unsigned query = 0;
      glGenQueries(1, &query);
      glBeginQuery(GL_TIME_ELAPSED, query);
      body();
      glEndQuery(GL_TIME_ELAPSED);
      queries_.emplace_back(f.timings.size(), query);
      f.timings.push_back({name, 0.0});
      return;
    }
    const std::string outer = passClock_ ? passClock_->stage() : std::string();
    if (passClock_) passClock_->setStage(name);
    FrameBackend::timeStage(f, name, [&] {
      body();
      finish(WaitFor::Timing);
    });
    if (passClock_) passClock_->setStage(outer);
  }
  void endFrame(FrameResult& f) override {
    finish(WaitFor::Timing);  // the frame's wall clock stops when its GL work is done
    for (const auto& [index, query] : queries_) {
      f.timings[index].ms = static_cast<double>(queryResult(query, WaitFor::Timing)) * 1e-6;
      glDeleteQueries(1, &query);
    }
    checkGl("timer queries");
    if (passClock_) {  // the draws after the clock (outputs, counts) are not the frame's
      f.passTimings = passClock_->take();
      passClock_.reset();
    }
    f.gl = processTraffic() - start_;  // the timed frame's talk with the host
    afterFrame_ = processTraffic();
  }

  // SPEC §11's counts, on the GPU (gpu/rule.h): the same counts as the host's (common/frame.h),
  // a small read at each decision. The edge sample is tested in the same pass as the hits, before
  // the floor is known, so that the early decision takes one read; where the floor rules the
  // method out it is not counted. --stages draws it apart too, to read it back.
  void countEarly(FrameResult& f, const std::function<bool(const FrameCounts&)>& wantSample) override {
    const unsigned shadowEdges = f.constants.effect == Effect::Ssm ? shadowTest_->texture(0) : 0;
    EdgeSampleInputs sample;
    if (wantSample) sample = {&f.constants.edges, shadowEdges};
    f.edgeSampled = gpu::countEarly(scene_, *gbuffers_[0], pcfSample_ ? pcfSample_->texture(0) : 0, sample,
                                    f.constants, f.counts, wantSample, &hitBits_);
    hitsCounted_ = true;  // H, which the report's idealSpeedupHit needs too
    if (keep_ && f.edgeSampled)
      f.edgeSample = readEdgeSample(*drawEdgeSample(scene_, *gbuffers_[0], f.constants.edges, shadowEdges));
  }
  void countStencils(FrameResult& f, const FrameMasks& masks) override {
    const std::shared_ptr<MaskTargets> targets = targetsOf(f, masks);
    gpu::countStencils(scene_, *gbuffers_[0], pcfSample_ ? pcfSample_->texture(0) : 0, targets->stencil, f.constants,
                       f.counts, hitBitsTexture());
  }
  // |S_ℓ| and the ideal speedups: on the host from the stencils read back (keepStages), else on
  // the GPU once the clock has stopped (countHitPixels).
  void countShaded(FrameResult& f) override {
    if (keep_) FrameBackend::countShaded(f);
  }
  void countHitPixels(FrameResult& f, FrameCounts* finalStencils) override {
    if (keep_) return FrameBackend::countHitPixels(f, finalStencils);
    gpu::countShaded(scene_, *gbuffers_[0], maskTargets_->stencil, f, hitsCounted_ ? f.counts.hitPixels : -1,
                     finalStencils, pcfSample_ ? pcfSample_->texture(0) : 0, hitBitsTexture());
  }

  // G-buffers: level 0 rasterised, the coarser levels subsampled from it.
  void gbuffer(FrameResult& f) override {
    drawGBuffer(scene_, f.view, gbufferTarget(f, 0));
    keepGBuffer(f, 0);
  }
  void subsampleGBuffer(FrameResult& f, int l) override {
    // SPEC §1: --coarse-gbuffer render rasterises the scene at the level's size (the same
    // full-res projection, so fragments sit at the level pixels' centres ((x+½)s, (y+½)s))
    if (f.constants.renderCoarseGBuffer)
      drawGBuffer(scene_, f.view, gbufferTarget(f, l));
    else
      gpu::subsampleGBuffer(scene_, *gbuffers_[0], f.constants.levels[static_cast<size_t>(l)], gbufferTarget(f, l));
    keepGBuffer(f, l);
  }
  void shadowMap(FrameResult& f) override {
    const int size = f.constants.ssm.shadowMapSize;
    f.shadowMap = shadowMapFrame(source_.light, scene_.bounds(), size);
    shadowMap_ = &scene_.shadowMapTarget(size);
    drawShadowMap(scene_, f.shadowMap, *shadowMap_);
    if (keep_) f.shadowMap.depth = shadowMap_->read();
  }
  void samplePcf(FrameResult& f) override {
    pcfSample_ = drawPcfSample(scene_, *gbuffers_[0], f.shadowMap, shadowMap_->texture(), f.view, f.constants.ssm);
    if (keep_) f.pcfSample = readPcfSample(*pcfSample_);
  }
  void sampleEdges(FrameResult& f) override {  // countEarly draws the sample itself; this reads it
    const unsigned shadowEdges = f.constants.effect == Effect::Ssm ? shadowTest_->texture(0) : 0;
    f.edgeSample = readEdgeSample(*drawEdgeSample(scene_, *gbuffers_[0], f.constants.edges, shadowEdges));
  }
  void shadowTest(FrameResult& f) override {
    shadowTest_ = scene_.target(gbuffers_[0]->width(), gbuffers_[0]->height(), 1, false, Texel::R8);
    drawShadowTest(scene_, *gbuffers_[0], f.shadowMap, shadowMap_->texture(), f.view, f.constants.ssm.biasTexels,
                   *shadowTest_);
    if (keep_) f.shadowLit = readShadowTest(*shadowTest_);
  }
  void edges(FrameResult& f) override {
    const unsigned shadowEdges = f.constants.effect == Effect::Ssm ? shadowTest_->texture(0) : 0;
    edges_ = drawEdges(scene_, *gbuffers_[0], f.constants.edges, shadowEdges, !keep_);
    if (keep_) f.edges = readEdges(*edges_);
  }

  // The mask builders (common/methods.h), each drawing on the GPU; host images only with keepStages.
  FrameMasks fullMasks(FrameResult& f) override {
    return made(drawFullMasks(scene_, f.constants), [&] { return fullModeMasks(f.constants); });
  }
  FrameMasks uniformMasks(FrameResult& f) override {
    return made(drawUniformMasks(scene_, f.constants), [&] { return mrr::uniformMasks(f.constants); });
  }
  FrameMasks edgeMasks(FrameResult& f) override { return drawnMasks(f, false); }
  FrameMasks effectMasks(FrameResult& f) override { return drawnMasks(f, true); }
  // masks.frag's pyramid from E; with `widened` (mrr-effect, SPEC §12) M_ℓ widened first by the
  // effect's footprint at the edges, drawn over E's blocks (effect_masks.frag).
  FrameMasks drawnMasks(FrameResult& f, bool widened) {
    const Constants& c = f.constants;
    Target footprint;
    FootprintFn drawF;
    if (widened)
      drawF = [&](const Cover& edgeBlocks) {
        footprint = drawFootprint(scene_, *gbuffers_[0], edges_->texture(0), edgeChannel(!keep_),
                                  c.needsShadowMap() ? &f.shadowMap : nullptr, shadowMap_ ? shadowMap_->texture() : 0,
                                  f.view, c, edgeBlocks);
        return footprint->texture(0);
      };
    const unsigned limit = levelLimit(f);
    std::shared_ptr<MaskTargets> targets = gpu::drawMasks(scene_, edges_->texture(0), edgeChannel(!keep_), c, drawF, limit);
    const MaskTargets* drawn = targets.get();
    return made(std::move(targets), [&] {
      Masks masks = readMasks(*drawn, c, false);
      if (masks[0].mask.empty()) masks[0].mask = f.edges.combined;  // M_0 = E (M'_0: mrr-effect, SPEC §13)
      return masks;
    });
  }
  FrameMasks tileMasks(FrameResult& f) override {
    // the rates on the GPU, SPEC §13's limit there too (limitTileRates' step)
    Target rates = drawTileRates(scene_, edges_->texture(0), edgeChannel(!keep_), edges_->width(), edges_->height(),
                                 levelLimit(f));
    if (keep_) f.tileRates = readTileRates(*rates);
    std::shared_ptr<MaskTargets> targets = drawTileMasks(scene_, std::move(rates), f.constants);
    const MaskTargets* drawn = targets.get();
    return made(std::move(targets), [&] { return readTileMasks(*drawn, f.tileRates, f.constants); });
  }
  // SPEC §13: limit.frag when a term is on (read back into f with keepStages: --stages, tiles'
  // host rates; else when the caller asks, after the frame); its texture, or 0.
  unsigned levelLimit(FrameResult& f) {
    if (!f.constants.foveation.active()) return 0;
    limit_ = drawLevelLimit(scene_, *gbuffers_[0], f.view, f.constants);
    if (keep_) readLevelLimit(*limit_, f.constants, f.eccentricity, f.motion, f.levelLimit);
    return limit_->texture(0);
  }
  void useMasks(FrameResult& f, const FrameMasks& masks, const StageFn& stage) override {
    if (masks.device) {
      maskTargets_ = targetsOf(f, masks);
      return;
    }
    // host images this backend did not draw: to the GPU
    stage(timedName(Timed::Stencils), [&] { maskTargets_ = uploadMasks(masks.host, f.constants); });
  }
  // The effect with the stencil test; SSAO then gets the bilateral blur.
  void shadeLevel(FrameResult& f, int l, const StageFn& stage) override {
    const Constants& c = f.constants;
    const size_t i = static_cast<size_t>(l);
    const LevelConstants& lc = c.levels[i];
    if (!lc.shaded) {  // uniform-k's level 0: a G-buffer, nothing shaded (c_0 = 0)
      raw_[i] = scene_.target(lc.width, lc.height, 1, false, effectTexel(c.channels()));
      raw_[i]->bind();
      const float zero[4] = {0, 0, 0, 0};
      glClearBufferfv(GL_COLOR, 0, zero);
      subTexture_[i] = raw_[i]->texture(0);
      if (keep_) f.levels[i].raw = f.levels[i].sub = ImageF(lc.width, lc.height, c.channels());
      return;
    }
    const Framebuffer& targets = *gbuffers_[i];
    const unsigned stencil = maskTargets_->stencil[i];
    // drawn masks know where S_ℓ can be set: the stencil fill covers those blocks alone
    const Cover fill = maskTargets_->drawn ? maskTargets_->supportCover(l) : Cover::whole();
    Target& raw = raw_[i];
    Target& sub = sub_[i];
    switch (c.effect) {
      case Effect::Ssao:
        stage(stageName(Part::Raw, l), [&] { raw = drawSsao(scene_, targets, stencil, f.view, lc, c.ssao, fill); });
        stage(stageName(Part::Sub, l),
              [&] { sub = drawBilateral(scene_, raw->texture(0), stencil, targets, c.bilateral, raw.get()); });
        break;
      case Effect::Ssm:  // PCF is its own filter: no blur (the paper blurs SSAO only)
        stage(stageName(Part::Raw, l), [&] {
          raw = drawSsm(scene_, targets, stencil, f.shadowMap, shadowMap_->texture(), f.view, c.ssm, fill);
        });
        break;
      case Effect::Ssgi: {
        const Target direct = scene_.target(lc.width, lc.height, 1, false);
        stage(timedName(Timed::Direct, l), [&] {
          drawDirectLight(scene_, targets, f.shadowMap, shadowMap_->texture(), f.view, source_.light, c.ssm.biasTexels,
                          *direct);
        });
        stage(stageName(Part::Raw, l),
              [&] { raw = drawSsgi(scene_, targets, direct->texture(0), stencil, f.view, lc, c.ssgi, fill); });
        break;
      }
    }
    const Framebuffer& result = sub ? *sub : *raw;
    subTexture_[i] = result.texture(0);
    if (keep_) {
      f.levels[i].raw = raw->read(0, c.channels());
      f.levels[i].sub = result.read(0, c.channels());
    }
  }

  // mrr-effect's a-posteriori term (SPEC §12.2): level ℓ's marks from its next coarser enabled
  // level's result (refinement_marks.frag), limited as M_ℓ was (masks.frag STEP 5), then M_ℓ, a_ℓ
  // and S_ℓ refined (refine_masks.frag with masks.frag's blur), near the marks' blocks (a block
  // map on the GPU). Read back with keepStages alone: |S_ℓ| is counted after the frame.
  void refineMasks(FrameResult& f, int l) override {
    const Constants& c = f.constants;
    const int next = c.nextCoarserEnabled(l);
    const size_t i = static_cast<size_t>(l), n = static_cast<size_t>(next);
    const LevelConstants& lc = c.levels[i];
    // the marks' blocks on the coarsest level's grid (2^{3−n} level-n pixels each): the
    // refinement is drawn near them and M_ℓ's (gpu::refineMasks)
    Target marksBlocks;
    const int blockSize = 1 << (kLevelCount - 1 - next);
    const int ratio = 1 << (next - l);
    Target marks;
    RefinementRecord& r = f.refinement[i];
    if (r.budgeted) {
      // SPEC §12.4: v(q), then the prices, keys, threshold and marks on the GPU (drawBudgetedSelection),
      // from what the refined level before this one left; the marks pooled into their blocks and
      // drawn as the τ_v path's. The record is filled after the clock (readOutputs).
      const Target range = drawRangeTest(scene_, subTexture_[n], c.channels(), maskTargets_->stencil[n],
                                         gbuffers_[n]->texture(0), c.effectMask.posterior,
                                         maskTargets_->supportCover(next), true);
      const Framebuffer* before = r.after >= 0 ? budget_[static_cast<size_t>(r.after)].state.get() : nullptr;
      BudgetedSelection& chosen = budget_[i];
      chosen = drawBudgetedSelection(scene_, range->texture(0), maskTargets_->stencil[i], gbuffers_[0]->texture(0),
                                     pcfSample_ ? pcfSample_->texture(0) : 0, c, l, next, r, before);
      marks = drawParentMarks(scene_, std::move(chosen.marks), ratio, lc.width, lc.height, &marksBlocks, blockSize);
    } else {
      marks = drawRefinementMarks(scene_, subTexture_[n], c.channels(), maskTargets_->stencil[n],
                                  gbuffers_[n]->texture(0), ratio, lc.width, lc.height, c.effectMask.posterior,
                                  maskTargets_->supportCover(next), &marksBlocks, blockSize);
    }
    if (limit_) marks = drawLevelLimited(scene_, marks->texture(0), l, limit_->texture(0), c);
    gpu::refineMasks(scene_, *maskTargets_, l, std::move(marks), c, BlockMap(*marksBlocks));
    refined_ = true;
    if (keep_) {
      MaskLevel& m = f.levels[i].masks;
      m.stencil = readStencil(l);
      m.mask = maskTargets_->refinedTarget[i]->readBinary(0);
      m.alpha = maskTargets_->alphaTarget[i]->read(0, 1);
      f.levels[i].marks = maskTargets_->marksTarget[i]->readBinary(0);
    }
  }

  void blend(FrameResult& f) override {
    const Constants& c = f.constants;
    if (methodInfo(c.mode).peer()) {
      std::array<const Framebuffer*, kLevelCount> targets{};
      for (size_t l = 0; l < targets.size(); ++l)
        if (c.levels[l].enabled) targets[l] = gbuffers_[l].get();
      const unsigned rates = maskTargets_->tileRates ? maskTargets_->tileRates->texture(0) : 0;
      f.blend = composePeer(scene_, subTexture_, c.channels(), targets, rates, c, keep_, final_.target);
      final_.attachment = 0;
      peerComposed_ = true;
      return;
    }
    std::array<LevelTextures, kLevelCount> inputs;
    for (size_t l = 0; l < inputs.size(); ++l) inputs[l] = {subTexture_[l], maskTargets_->stencil[l], maskTargets_->alpha[l]};
    // a refined level's α reaches past the edge blocks' neighbourhood (SPEC §12.2): blended everywhere
    const BlockMap nearBlocks = maskTargets_->drawn && !refined_ ? maskTargets_->blendNear : BlockMap();
    f.blend = blendLevels(scene_, inputs, c.channels(), c, keep_, nearBlocks, &final_);
  }
  // SPEC §14: temporal.frag with the previous frame's history, uploaded; final' becomes the image
  // shade.frag reads (the blend's target kept for its level map). The history for the next frame
  // is read back after the clock (readOutputs).
  void temporal(FrameResult& f, const FrameHistory* history) override {
    const Constants& c = f.constants;
    if (!history || history->empty()) return;
    Target t = drawTemporal(scene_, final_.texture(), *gbuffers_[0], maskTargets_->stencil[0], maskTargets_->alpha[0],
                            *history, f.view, c);
    if (keep_) {
      f.temporal.result = t->read(0, c.channels());
      const ImageF aux = t->read(1);
      f.temporal.history = ImageF::uninitialised(c.width, c.height, c.channels());
      f.temporal.weight = ImageF::uninitialised(c.width, c.height, 1);
      for (size_t i = 0; i < aux.pixelCount(); ++i) {
        for (size_t k = 0; k < static_cast<size_t>(c.channels()); ++k)
          f.temporal.history.data[i * static_cast<size_t>(c.channels()) + k] = aux.data[4 * i + k];
        f.temporal.weight.data[i] = aux.data[4 * i + 3];
      }
      f.temporal.previous = std::make_shared<const FrameHistory>(*history);
    }
    blended_ = std::move(final_);
    final_ = GpuImage{std::move(t), 0};
  }
  // The shaded image (shade.frag), from the level-0 G-buffer and the final image on the GPU.
  void shade(FrameResult& f) override {
    shaded_ = drawShade(scene_, *gbuffers_[0], final_.texture(), shadowTest_ ? shadowTest_->texture(0) : 0, f.view,
                        source_.light, f.constants);
    if (keep_) f.shaded = shaded_->read(0, 3);
  }

  // After the frame: what the caller asked for, read back (RenderOptions::outputs), and the
  // traffic since the frame's clock stopped.
  void readOutputs(FrameResult& f) {
    const Constants& c = f.constants;
    readBudget(f);
    const GpuImage& blended = blended_.target ? blended_ : final_;  // the blend's (or composition's) target
    // the temporal term's next frame reads final' (FrameHistory)
    const bool wantFinal = (outputs_ & kOutputFinal) || c.temporal.on();
    if (!keep_) {
      if (wantFinal) {
        if (peerComposed_) {
          readComposed(*blended.target, c.channels(), f.blend);
        } else {
          f.blend.final = blended.target->read(0, c.channels());
          f.blend.levelMap = blended.target->readBytes(1);
        }
      }
      // SPEC §14: final' where the temporal term ran, for the image written and the next frame
      if (blended_.target && wantFinal)
        f.temporal.result = final_.target->read(0, c.channels());
      if (outputs_ & kOutputShaded) f.shaded = shaded_->read(0, 3);
      if (outputs_ & kOutputStencils) {
        const Masks stencils = readMasks(*maskTargets_, c, true);
        for (size_t l = 0; l < kLevelCount; ++l) f.levels[l].masks.stencil = stencils[l].stencil;
      }
      if (outputs_ & kOutputMaps) {
        if (limit_) readLevelLimit(*limit_, c, f.eccentricity, f.motion, f.levelLimit);
        if (maskTargets_->tileRates) f.tileRates = readTileRates(*maskTargets_->tileRates);
      }
    }
    // SPEC §14: the history the next frame's temporal term reads (level 0's depth and normal, final')
    if (c.temporal.on()) {
      f.history = readHistory(*gbuffers_[0], f.final(), f.view, c);
      for (size_t l = 0; l < kLevelCount; ++l) f.history.marked[l] = f.levels[l].marked;  // SPEC §14.2
    }
    f.glProcess = processTraffic();
    f.glAfterFrame = f.glProcess - afterFrame_;
  }

 private:
  // SPEC §12.4, after the clock: each budgeted level's state and counts in one small read; its
  // marks (step 9's, as the GPU drew them) where the next frame's hysteresis reads them, and its
  // candidates' prices where the stages are kept (as the oracle's record).
  void readBudget(FrameResult& f) {
    CountBatch batch(scene_);
    std::array<size_t, kLevelCount> at{}, counted{};
    size_t targets = 0;
    for (size_t l = 0; l < kLevelCount; ++l) {
      if (!f.refinement[l].budgeted || !budget_[l].state) continue;
      at[l] = batch.add(drawBudgetCounts(scene_, budget_[l]));
      counted[l] = targets;
      batch.add(std::move(budget_[l].state));  // a 1×1 target sums to itself
      targets += 2;
    }
    const std::vector<int64_t> values = batch.read();
    if (values.empty()) return;
    const bool wantMarks = keep_ || f.constants.temporal.on();
    for (size_t l = 0; l < kLevelCount; ++l) {
      RefinementRecord& r = f.refinement[l];
      if (!r.budgeted || !budget_[l].candidates) continue;
      const int64_t* counts = &values[at[l]];
      const int64_t* state = counts + 4;
      r.threshold = static_cast<uint32_t>(state[0]);
      r.leftUnits = static_cast<uint32_t>(state[1]);
      r.spentUnits = static_cast<uint32_t>(state[2]);
      r.shareUnits = static_cast<uint32_t>(state[3]);
      r.candidates = counts[0];
      r.taken = counts[1];
      r.kept = counts[2];
      if (wantMarks) {  // (candidate, marked, kept, 0) per candidate
        const Target perCandidate = batch.take(counted[l]);
        const std::vector<uint32_t> texels = perCandidate->readUint(0);
        ImageU8 marked(perCandidate->width(), perCandidate->height());
        for (size_t k = 0; k < marked.data.size(); ++k) marked.data[k] = static_cast<uint8_t>(texels[4 * k + 1]);
        f.levels[l].marked = std::move(marked);
      }
      if (keep_) {  // (price, key, before, 0)
        const std::vector<uint32_t> texels = budget_[l].candidates->readUint(0);
        r.candidatePrices.resize(texels.size() / 4);
        for (size_t k = 0; k < r.candidatePrices.size(); ++k) r.candidatePrices[k] = texels[4 * k];
      }
    }
  }
  // Level ℓ's G-buffer targets, fresh from the pool. A coarse level's albedo is read only by
  // SSGI's direct light (and --stages): the resident frame leaves that target out otherwise.
  const Framebuffer& gbufferTarget(const FrameResult& f, int l) {
    const Constants& c = f.constants;
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const int targets = keep_ || l == 0 || c.effect == Effect::Ssgi ? 3 : 2;
    Target& g = gbuffers_[static_cast<size_t>(l)];
    g = scene_.target(lc.width, lc.height, targets, true);
    return *g;
  }
  // countEarly's per-block hit bits (rule.frag step 1's counts2), where it ran: countStencils reads
  // a level pixel's hit there
  unsigned hitBitsTexture() const { return hitBits_ ? hitBits_->texture(2) : 0; }
  ImageU8 readStencil(int l) const {  // S_ℓ: its own target, or beside a_ℓ where no mark refined it
    const size_t i = static_cast<size_t>(l);
    return maskTargets_->stencilTarget[i] ? maskTargets_->stencilTarget[i]->readBinary(0)
                                          : maskTargets_->alphaTarget[i]->readBinary(1);
  }
  void keepGBuffer(FrameResult& f, int l) {  // --stages, probe, compare: read back
    if (keep_) f.levels[static_cast<size_t>(l)].gbuffer = readGBuffer(*gbuffers_[static_cast<size_t>(l)]);
  }
  // A builder's result: the port's targets, and with keepStages the host images `host` reads.
  FrameMasks made(std::shared_ptr<MaskTargets> targets, const std::function<Masks()>& host) const {
    FrameMasks m;
    if (keep_) m.host = host();
    m.device = std::move(targets);
    return m;
  }
  // The port's targets behind `masks` (host images alone are uploaded).
  std::shared_ptr<MaskTargets> targetsOf(const FrameResult& f, const FrameMasks& masks) const {
    if (auto targets = std::dynamic_pointer_cast<MaskTargets>(masks.device)) return targets;
    return uploadMasks(masks.host, f.constants);
  }

  const GpuScene& scene_;
  const Scene& source_;  // its light
  const bool timerQueries_, keep_;
  const unsigned outputs_;
  std::array<BudgetedSelection, kLevelCount> budget_;  // SPEC §12.4's selection per budgeted level
  const GlTraffic start_;  // the process's traffic when the frame began
  GlTraffic afterFrame_;   // ... when its clock stopped
  std::vector<std::pair<size_t, unsigned>> queries_;
  std::optional<PassClock> passClock_;  // --gpu-timing passes: every draw of the timed frame
  std::array<Target, kLevelCount> gbuffers_;
  const ShadowMapTarget* shadowMap_ = nullptr;  // the scene's, kept from frame to frame
  Target shadowTest_, edges_, pcfSample_;
  Target hitBits_;  // countEarly's step-1 target
  std::shared_ptr<MaskTargets> maskTargets_;
  std::array<Target, kLevelCount> raw_, sub_;
  std::array<unsigned, kLevelCount> subTexture_{};
  GpuImage final_;
  GpuImage blended_;  // the blend's target, where the temporal term replaced final_
  Target shaded_;
  bool peerComposed_ = false;  // final_ is composePeer's target (its level map a float in target 1)
  Target limit_;  // SPEC §13's level limit (limit.frag), when a term is on
  bool refined_ = false;  // SPEC §12.2 refined a level's masks (refineMasks)
  bool hitsCounted_ = false;  // the rule counted H (f.counts.hitPixels)
};
}  // namespace

FrameResult GpuRenderer::render(const Camera& camera, const Constants& constants, const RenderOptions& options) const {
  PortFrame backend(gpuScene_, scene_, timerQueries_, passTiming_, options);
  FrameResult f = renderFrame(backend, scene_.light, camera, constants, options);
  backend.readOutputs(f);  // after the clock: what the caller asked for
  return f;
}

}  // namespace mrr::gpu
