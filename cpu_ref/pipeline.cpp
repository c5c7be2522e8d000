#include "cpu_ref/pipeline.h"

#include <chrono>
#include <vector>

#include "common/driver.h"
#include "common/stages.h"
#include "cpu_ref/temporal.h"

namespace mrr {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
}  // namespace

Renderer::Renderer(const Scene& scene) : scene_(scene), rays_(scene), stages_(scene.light, &rays_) {
  bvhBuildMs_ = msSince(buildStart_);
}

namespace {
// The oracle's side of the frame contract (common/driver.h): every stage of cpu_ref/oracle.h on
// host images, written straight into the FrameResult, which therefore always holds every stage.
class OracleFrame final : public FrameBackend {
 public:
  OracleFrame(const OracleStages& stages, const RenderOptions& options) : stages_(stages), options_(options) {}

  const char* pathName() const override { return "cpu"; }

  void gbuffer(FrameResult& f) override { f.levels[0].gbuffer = stages_.gbuffer(f.view, f.constants.levels[0]); }
  void subsampleGBuffer(FrameResult& f, int l) override { f.levels[static_cast<size_t>(l)].gbuffer = stages_.coarseGBuffer(f, l); }
  void shadowMap(FrameResult& f) override { f.shadowMap = stages_.shadowMap(f.constants); }
  void samplePcf(FrameResult& f) override { f.pcfSample = stages_.pcfSample(f); }
  void sampleEdges(FrameResult& f) override { f.edgeSample = stages_.edgeSample(f); }
  void shadowTest(FrameResult& f) override { f.shadowLit = stages_.shadowTest(f); }
  void edges(FrameResult& f) override { f.edges = stages_.edges(f); }
  FrameMasks edgeMasks(FrameResult& f) override {
    limit(f);
    return stages_.edgeMasks(f);
  }
  FrameMasks effectMasks(FrameResult& f) override {
    limit(f);
    return stages_.effectMasks(f);
  }
  FrameMasks tileMasks(FrameResult& f) override {
    limit(f);
    return stages_.tileMasks(f, f.tileRates);
  }
  // SPEC §13: the eccentricity, motion and level limit into f, when a term is on (the masks read it).
  void limit(FrameResult& f) const {
    if (!f.constants.foveation.active()) return;
    LevelLimit ll = stages_.levelLimit(f);
    f.eccentricity = std::move(ll.eccentricity);
    f.motion = std::move(ll.motion);
    f.levelLimit = std::move(ll.limit);
  }

  void shadeLevel(FrameResult& f, int l, const StageFn& stage) override {
    const Constants& c = f.constants;
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    if (!lc.shaded) {  // uniform-k's level 0: a G-buffer, nothing shaded
      lr.raw = lr.sub = ImageF(lc.width, lc.height, c.channels());
      return;
    }
    lr.raw = stages_.raw(f, l, stage, options_.progress);
    if (c.effect == Effect::Ssao)
      stage(stageName(Part::Sub, l), [&] { lr.sub = stages_.sub(f, l, lr.raw); });
    else
      lr.sub = stages_.sub(f, l, lr.raw);
  }

  void refineMasks(FrameResult& f, int l) override {
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    RefinementRecord& r = f.refinement[static_cast<size_t>(l)];  // SPEC §12.4: what the budget bought
    if (r.budgeted && r.after >= 0) {  // what the refined level before this one left
      const RefinementRecord& before = f.refinement[static_cast<size_t>(r.after)];
      r.leftUnits = before.leftUnits - before.spentUnits;
    }
    RefinementSelection selection;
    ImageU8 marks = stages_.marks(f, l, &selection);
    if (r.budgeted) {
      r.shareUnits = levelShare(r.leftUnits, r.levelsLeft);
      r.spentUnits = selection.spent;
      r.threshold = selection.threshold;
      r.candidates = selection.candidates;
      r.taken = selection.taken;
      r.kept = selection.kept;
      r.candidatePrices = std::move(selection.prices);
      f.levels[static_cast<size_t>(l)].marked = std::move(selection.varies);
    }
    stages_.refine(lr.masks, marks, f.constants.levels[static_cast<size_t>(l)]);
    lr.marks = std::move(marks);
  }

  void blend(FrameResult& f) override { f.blend = stages_.blend(f, options_.keepStages); }
  void temporal(FrameResult& f, const FrameHistory* history) override {
    if (history && !history->empty()) {
      f.temporal = stages_.temporal(f, *history);
      if (options_.keepStages) f.temporal.previous = std::make_shared<const FrameHistory>(*history);
    }
    f.history = makeHistory(f);
  }
  void shade(FrameResult& f) override { f.shaded = stages_.shaded(f); }

 private:
  const OracleStages& stages_;
  const RenderOptions& options_;
};
}  // namespace

FrameResult Renderer::render(const Camera& camera, const Constants& constants, const RenderOptions& options) const {
  OracleFrame backend(stages_, options);
  return renderFrame(backend, scene_.light, camera, constants, options);
}

}  // namespace mrr
