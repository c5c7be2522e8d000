#include "gpu/pipeline.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <chrono>
#include <utility>
#include <vector>

#include "common/cost_model.h"
#include "common/driver.h"
#include "common/effect_budget.h"
#include "common/error.h"
#include "common/stages.h"
#include "gpu/bilateral.h"
#include "gpu/blend.h"
#include "gpu/edges.h"
#include "gpu/effect_masks.h"
#include "gpu/gbuffer.h"
#include "gpu/masks.h"
#include "gpu/peers.h"
#include "gpu/program.h"
#include "gpu/shade.h"
#include "gpu/shadowmap.h"
#include "gpu/ssao.h"
#include "gpu/ssgi.h"
#include "gpu/ssm.h"
#include "gpu/stencil.h"
#include "gpu/temporal.h"

namespace mrr::gpu {

bool isPortOnlyStage(const std::string& stage) {
  const std::optional<TimedStage> t = findTimed(stage);
  return t && t->info().on == TimedOn::Port;
}

GpuTiming parseGpuTiming(const std::string& name) {
  if (name == "auto") return GpuTiming::Auto;
  if (name == "wall") return GpuTiming::Wall;
  if (name == "query") return GpuTiming::Query;
  throw MrrError("--gpu-timing " + name + ": unknown timing (expected auto, wall or query)");
}

GpuRenderer::GpuRenderer(const Scene& scene, int deviceIndex, GpuTiming timing)
    : scene_(scene), context_(deviceIndex), gpuScene_(scene),
      timerQueries_(usesTimerQueries(timing, context_.renderer())) {}

bool usesTimerQueries(GpuTiming timing, const std::string& renderer) {
  const bool software =
      renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
  return timing == GpuTiming::Query || (timing == GpuTiming::Auto && !software);
}

std::string GpuRenderer::timingMethod() const {
  if (timerQueries_)
    return "GL_TIME_ELAPSED queries around each stage's GL work (no glFinish between stages); total on the wall "
           "clock";
  return "glFinish + wall clock around each stage (timer queries are wrong on llvmpipe); each stage's readbacks are "
         "inside its timing (with --stages or probe every stage is read back, else only S_l, the final image, level "
         "map and shaded image)";
}

namespace {
// The port's side of the frame contract (common/driver.h). Every stage's images stay on the
// GPU; the frame reads back S_ℓ (for |S_ℓ| and the never-slower rule, before anything is
// shaded), the final image and level map, and the shaded image. With keepStages (--stages,
// probe, compare) every stage is read back too, into the structures the oracle fills.
class PortFrame final : public FrameBackend {
 public:
  PortFrame(const GpuScene& scene, const Scene& source, bool timerQueries,
            const RenderOptions& options)
      : scene_(scene), source_(source), timerQueries_(timerQueries), keep_(options.keepStages) {}

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
    FrameBackend::timeStage(f, name, [&] {
      body();
      glFinish();
    });
  }
  void endFrame(FrameResult& f) override {
    glFinish();
    for (const auto& [index, query] : queries_) {
      GLuint64 ns = 0;
      glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
      f.timings[index].ms = static_cast<double>(ns) * 1e-6;
      glDeleteQueries(1, &query);
    }
    checkGl("timer queries");
  }

  const ImageU8& fullResHit(const FrameResult& f) override {
    if (!f.levels[0].gbuffer.hit.empty() || !gbuffers_[0]) return f.levels[0].gbuffer.hit;
    if (hit_.empty()) {  // read once a frame: the rule's counts, then idealSpeedupHit
      // The view-space z alone (a quarter of the texels' bytes): < 0 on geometry, in front of the
      // camera, and 0 where the target was cleared (background), as hit in w.
      const ImageF z = gbuffers_[0]->readChannel(0, 2);
      hit_ = ImageU8::uninitialised(z.width, z.height);
      for (size_t i = 0; i < hit_.data.size(); ++i) hit_.data[i] = z.data[i] < 0.0f ? 1 : 0;
    }
    return hit_;
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
    shadowMap_ = std::make_unique<ShadowMapTarget>(size);
    drawShadowMap(scene_, f.shadowMap, *shadowMap_);
    if (keep_) f.shadowMap.depth = shadowMap_->read();
  }
  void samplePcf(FrameResult& f) override {
    f.pcfSample = drawPcfSample(scene_, *gbuffers_[0], f.shadowMap, shadowMap_->texture(), f.view, f.constants.ssm);
  }
  void sampleEdges(FrameResult& f) override {
    const unsigned shadowEdges = f.constants.effect == Effect::Ssm ? shadowTest_->texture(0) : 0;
    f.edgeSample = drawEdgeSample(scene_, *gbuffers_[0], f.constants.edges, shadowEdges);
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
  Masks edgeMasks(FrameResult& f) override { return drawnMasks(f, false); }
  Masks effectMasks(FrameResult& f) override { return drawnMasks(f, true); }
  // masks.frag's pyramid from E; with `widened` (mrr-effect, SPEC §12) M_ℓ widened first by the
  // effect's footprint at the edges, drawn over E's blocks (effect_masks.frag).
  Masks drawnMasks(FrameResult& f, bool widened) {
    const Constants& c = f.constants;
    Target footprint;
    FootprintFn drawF;
    if (widened)
      drawF = [&](const std::vector<glm::ivec4>& edgeRects) {
        footprint = drawFootprint(scene_, *gbuffers_[0], edges_->texture(0), edgeChannel(!keep_),
                                  c.needsShadowMap() ? &f.shadowMap : nullptr, shadowMap_ ? shadowMap_->texture() : 0,
                                  f.view, c, &edgeRects);
        return footprint->texture(0);
      };
    const unsigned limit = levelLimit(f);
    maskTargets_ = gpu::drawMasks(scene_, edges_->texture(0), edgeChannel(!keep_), c, drawF, limit);
    Masks masks = readMasks(*maskTargets_, c, !keep_);
    if (keep_ && masks[0].mask.empty()) masks[0].mask = f.edges.combined;  // M_0 = E (M'_0: mrr-effect, SPEC §13)
    return masks;
  }
  Masks tileMasks(FrameResult& f) override {
    f.tileRates = tileRates(scene_, edges_->texture(0), edgeChannel(!keep_), edges_->width(), edges_->height());
    if (levelLimit(f)) limitTileRates(f.tileRates, f.levelLimit);  // SPEC §13, the same host step as the oracle's
    return gpu::tileMasks(scene_, f.tileRates, f.constants);
  }
  // SPEC §13: limit.frag when a term is on, read back into f (the report, tiles, --stages); its
  // texture, or 0.
  unsigned levelLimit(FrameResult& f) {
    if (!f.constants.foveation.active()) return 0;
    limit_ = drawLevelLimit(scene_, *gbuffers_[0], f.view, f.constants);
    readLevelLimit(*limit_, f.constants, f.eccentricity, f.motion, f.levelLimit);
    return limit_->texture(0);
  }
  void useMasks(FrameResult& f, const Masks& masks, const StageFn& stage) override {
    if (!maskTargets_ || !maskTargets_->drawn || f.fallback.fellBack)  // host stencils: to the GPU
      stage(timedName(Timed::Stencils), [&] { maskTargets_ = uploadMasks(masks, f.constants); });
  }
  // The effect with the stencil test; SSAO then gets the bilateral blur.
  void shadeLevel(FrameResult& f, int l, const StageFn& stage) override {
    const Constants& c = f.constants;
    const size_t i = static_cast<size_t>(l);
    const LevelConstants& lc = c.levels[i];
    if (!lc.shaded) {  // uniform-k's level 0: a G-buffer, nothing shaded (c_0 = 0)
      const ImageF zero(lc.width, lc.height, c.channels());
      subTexture_[i] = unshaded_.add(uploadTexture(zero));
      if (keep_) f.levels[i].raw = f.levels[i].sub = zero;
      return;
    }
    const Framebuffer& targets = *gbuffers_[i];
    const unsigned stencil = maskTargets_->stencil[i];
    // drawn masks know where S_ℓ can be set: the stencil fill covers those rectangles alone
    const std::vector<glm::ivec4>* fill =
        maskTargets_->drawn && !maskTargets_->supportRects[i].empty() ? &maskTargets_->supportRects[i] : nullptr;
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
  // and S_ℓ refined (refine_masks.frag with masks.frag's blur). S_ℓ is read back for |S_ℓ|.
  void refineMasks(FrameResult& f, int l) override {
    const Constants& c = f.constants;
    const int next = c.nextCoarserEnabled(l);
    const size_t i = static_cast<size_t>(l), n = static_cast<size_t>(next);
    const LevelConstants& lc = c.levels[i];
    // the marks' blocks on the coarsest level's grid (2^{3−n} level-n pixels each): the
    // refinement is drawn near them and M_ℓ's (gpu::refineMasks)
    ImageU8 marksBlocks;
    const int blockSize = 1 << (kLevelCount - 1 - next);
    Target marks;
    RefinementRecord& r = f.refinement[i];
    if (r.budgeted) {
      // SPEC §12.4: v(q) read back, the marks selected on the host (common/effect_budget.h) and drawn
      const Target range = drawRangeTest(scene_, subTexture_[n], c.channels(), maskTargets_->stencil[n],
                                         gbuffers_[n]->texture(0), c.effectMask.posterior,
                                         &maskTargets_->supportRects[n], true);
      const std::vector<double> prices =
          candidatePrices(f.levels[i].masks.stencil, fullResHit(f), f.pcfSample, c, l, next, r.prices);
      RefinementSelection chosen =
          selectRefinement(range->read(0, 1), prices, r.budgetNs, c.effectMask.posterior, c.effectMask.hysteresis,
                           r.previousMarked.empty() ? nullptr : &r.previousMarked);
      r.spentNs = chosen.spentNs;
      r.candidates = chosen.candidates;
      r.taken = chosen.taken;
      r.kept = chosen.kept;
      r.candidatePrices = prices;
      marksBlocks = blocksOf(chosen.varies, blockSize);
      TextureSet uploaded;
      const unsigned varies = uploaded.add(uploadBinary(chosen.varies));
      const std::vector<glm::ivec4> rects =
          markedRects(marksBlocks, blockSize, 1 << (next - l), range->width(), range->height(), lc.width, lc.height);
      marks = drawParentMarks(scene_, varies, 1 << (next - l), lc.width, lc.height, &rects);
      f.levels[i].marked = std::move(chosen.varies);
    } else {
      marks = drawRefinementMarks(scene_, subTexture_[n], c.channels(), maskTargets_->stencil[n],
                                  gbuffers_[n]->texture(0), 1 << (next - l), lc.width, lc.height,
                                  c.effectMask.posterior, &maskTargets_->supportRects[n], &marksBlocks, blockSize);
    }
    if (limit_) marks = drawLevelLimited(scene_, marks->texture(0), l, limit_->texture(0), c);
    gpu::refineMasks(scene_, *maskTargets_, l, std::move(marks), c, &marksBlocks);
    refined_ = true;
    MaskLevel& m = f.levels[i].masks;
    m.stencil = maskTargets_->stencilTarget[i] ? maskTargets_->stencilTarget[i]->readBinary(0)  // no mark: S_ℓ
                                               : maskTargets_->alphaTarget[i]->readBinary(1);  // beside a_ℓ still
    if (keep_) {
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
      f.blend = composePeer(scene_, subTexture_, c.channels(), targets, f.tileRates, c, keep_, &final_);
      return;
    }
    std::array<LevelTextures, kLevelCount> inputs;
    for (size_t l = 0; l < inputs.size(); ++l) inputs[l] = {subTexture_[l], maskTargets_->stencil[l], maskTargets_->alpha[l]};
    // a refined level's α reaches past the edge blocks' neighbourhood (SPEC §12.2): blended everywhere
    const ImageU8* edgeBlocks = maskTargets_->drawn && !refined_ ? &maskTargets_->edgeBlocks : nullptr;
    f.blend = blendLevels(scene_, inputs, c.channels(), c, keep_, edgeBlocks, &final_, &maskTargets_->widenedBy);
  }
  // SPEC §14: temporal.frag with the previous frame's history, uploaded; final' becomes the image
  // shade.frag reads. Then, either way, the history for the next frame (level 0's depth and normal
  // read back).
  void temporal(FrameResult& f, const FrameHistory* history) override {
    const Constants& c = f.constants;
    if (history && !history->empty()) {
      Target t = drawTemporal(scene_, final_.texture(), *gbuffers_[0], maskTargets_->stencil[0],
                              maskTargets_->alpha[0], *history, f.view, c);
      f.temporal.result = t->read(0, c.channels());
      if (keep_) {
        const ImageF aux = t->read(1);
        f.temporal.history = ImageF::uninitialised(c.width, c.height, c.channels());
        f.temporal.weight = ImageF::uninitialised(c.width, c.height, 1);
        for (size_t i = 0; i < aux.pixelCount(); ++i) {
          for (size_t k = 0; k < static_cast<size_t>(c.channels()); ++k)
            f.temporal.history.data[i * static_cast<size_t>(c.channels()) + k] = aux.data[4 * i + k];
          f.temporal.weight.data[i] = aux.data[4 * i + 3];
        }
      }
      final_ = GpuImage{std::move(t), 0};
      if (keep_) f.temporal.previous = std::make_shared<const FrameHistory>(*history);
    }
    f.history = readHistory(*gbuffers_[0], f.final(), f.view, c);
    for (size_t l = 0; l < kLevelCount; ++l) f.history.marked[l] = f.levels[l].marked;  // SPEC §14.2
  }
  // The shaded image (shade.frag), from the level-0 G-buffer and the final image on the GPU.
  void shade(FrameResult& f) override {
    f.shaded = drawShade(scene_, *gbuffers_[0], final_.texture(), shadowTest_ ? shadowTest_->texture(0) : 0, f.view,
                         source_.light, f.constants);
  }

 private:
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
  void keepGBuffer(FrameResult& f, int l) {  // --stages, probe, compare: read back
    if (keep_) f.levels[static_cast<size_t>(l)].gbuffer = readGBuffer(*gbuffers_[static_cast<size_t>(l)]);
  }

  const GpuScene& scene_;
  const Scene& source_;  // its light
  const bool timerQueries_, keep_;
  ImageU8 hit_;  // the full-res hit flags, read back once (fullResHit)
  std::vector<std::pair<size_t, unsigned>> queries_;
  std::array<Target, kLevelCount> gbuffers_;
  std::unique_ptr<ShadowMapTarget> shadowMap_;
  Target shadowTest_, edges_;
  std::unique_ptr<MaskTargets> maskTargets_;
  std::array<Target, kLevelCount> raw_, sub_;
  std::array<unsigned, kLevelCount> subTexture_{};
  TextureSet unshaded_;
  GpuImage final_;
  Target limit_;  // SPEC §13's level limit (limit.frag), when a term is on
  bool refined_ = false;  // SPEC §12.2 refined a level's masks (refineMasks)
};
}  // namespace

FrameResult GpuRenderer::render(const Camera& camera, const Constants& constants, const RenderOptions& options) const {
  PortFrame backend(gpuScene_, scene_, timerQueries_, options);
  return renderFrame(backend, scene_.light, camera, constants, options);
}

}  // namespace mrr::gpu
