#include "cpu_ref/pipeline.h"

#include <chrono>
#include <vector>

#include "common/driver.h"
#include "common/parallel.h"
#include "common/stages.h"
#include "cpu_ref/bilateral.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/foveation.h"
#include "cpu_ref/peers.h"
#include "cpu_ref/shade.h"
#include "cpu_ref/ssgi.h"
#include "cpu_ref/ssm.h"
#include "cpu_ref/ssao.h"

namespace mrr {

namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
}  // namespace

Renderer::Renderer(const Scene& scene) : scene_(scene), rays_(scene) { bvhBuildMs_ = msSince(buildStart_); }

namespace {
// The oracle's side of the frame contract (common/driver.h): every stage on host images,
// written straight into the FrameResult, which therefore always holds every stage.
class OracleFrame final : public FrameBackend {
 public:
  OracleFrame(const Scene& scene, const RayScene& rays, std::array<OccluderPlanes, kLevelCount>& planes,
              const RenderOptions& options)
      : scene_(scene), rays_(rays), planes_(planes), options_(options) {}

  const char* pathName() const override { return "cpu"; }

  void gbuffer(FrameResult& f) override { f.levels[0].gbuffer = renderGBuffer(rays_, f.view, f.constants.levels[0]); }
  void subsampleGBuffer(FrameResult& f, int l) override {
    const LevelConstants& level = f.constants.levels[static_cast<size_t>(l)];
    // SPEC §1: --coarse-gbuffer render casts a ray at each level pixel's centre ((x+½)s, (y+½)s)
    f.levels[static_cast<size_t>(l)].gbuffer = f.constants.renderCoarseGBuffer
                                                   ? renderGBuffer(rays_, f.view, level)
                                                   : mrr::subsampleGBuffer(f.levels[0].gbuffer, level);
  }
  void shadowMap(FrameResult& f) override {
    f.shadowMap = renderShadowMap(rays_, scene_.light, scene_.bounds(), f.constants.ssm.shadowMapSize);
  }
  void samplePcf(FrameResult& f) override {
    f.pcfSample = pcfSample(f.levels[0].gbuffer, f.shadowMap, f.view, f.constants.ssm);
  }
  void sampleEdges(FrameResult& f) override {
    const ImageU8* shadowEdges = f.constants.effect == Effect::Ssm ? &f.shadowLit : nullptr;
    f.edgeSample = edgeSample(f.levels[0].gbuffer, f.constants.edges, shadowEdges);
  }
  void shadowTest(FrameResult& f) override {
    f.shadowLit = shadowTestImage(f.levels[0].gbuffer, f.shadowMap, f.view, f.constants.ssm.biasTexels);
  }
  void edges(FrameResult& f) override {
    const ImageU8* shadowEdges = f.constants.effect == Effect::Ssm ? &f.shadowLit : nullptr;
    f.edges = detectEdges(f.levels[0].gbuffer, f.constants.edges, shadowEdges);
  }
  Masks methodMasks(FrameResult& f) override {
    const ImageU8* limit = levelLimitOf(f);
    if (f.constants.mode != Mode::MrrEffect) return buildMasks(f.edges.combined, f.constants, nullptr, limit);
    // SPEC §12: the effect's footprint at the edges, then the paper's masks from widened M_ℓ.
    const ImageF footprint = effectFootprint(f.levels[0].gbuffer, f.edges.combined, f.view,
                                             f.constants.needsShadowMap() ? &f.shadowMap : nullptr, f.constants);
    return buildMasks(f.edges.combined, f.constants, &footprint, limit);
  }
  Masks tileMasks(FrameResult& f) override {
    f.tileRates = tileRates(f.edges.combined);
    if (const ImageU8* limit = levelLimitOf(f)) limitTileRates(f.tileRates, *limit);  // SPEC §13
    return mrr::tileMasks(f.tileRates, f.constants);
  }
  // SPEC §13: the eccentricity, motion and level limit into f, when a term is on; null otherwise.
  static const ImageU8* levelLimitOf(FrameResult& f) {
    if (!f.constants.foveation.active()) return nullptr;
    LevelLimit ll = levelLimit(f.levels[0].gbuffer, f.view, f.constants);
    f.eccentricity = std::move(ll.eccentricity);
    f.motion = std::move(ll.motion);
    f.levelLimit = std::move(ll.limit);
    return &f.levelLimit;
  }

  void shadeLevel(FrameResult& f, int l, const StageFn& stage) override {
    const Constants& c = f.constants;
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    if (!lc.shaded) {  // uniform-k's level 0: a G-buffer, nothing shaded
      lr.raw = lr.sub = ImageF(lc.width, lc.height, c.channels());
      return;
    }
    switch (c.effect) {
      case Effect::Ssao: {
        OccluderPlanes& planes = planes_[static_cast<size_t>(l)];
        stage(timedName(Timed::Planes, l), [&] { occluderPlanes(lr.gbuffer, planes); });
        // Long stages (over ~2·10⁸ samples, seconds on 2 cores) also report their tenths.
        std::function<void(double)> tenths;
        const double work = static_cast<double>(lc.width) * lc.height * c.ssao.samples;
        if (options_.progress && work > 2e8)
          tenths = [&](double done) {
            options_.progress(stageName(Part::Raw, l) + " " + std::to_string(static_cast<int>(done * 100 + 0.5)) + "%");
          };
        stage(stageName(Part::Raw, l),
              [&] { lr.raw = renderSsao(lr.gbuffer, planes, lr.masks.stencil, f.view, lc, c.ssao, tenths); });
        stage(stageName(Part::Sub, l), [&] { lr.sub = bilateralBlur(lr.raw, lr.masks.stencil, lr.gbuffer, c.bilateral); });
        break;
      }
      case Effect::Ssm:
        stage(stageName(Part::Raw, l), [&] { lr.raw = renderSsm(lr.gbuffer, f.shadowMap, lr.masks.stencil, f.view, c.ssm); });
        lr.sub = lr.raw;  // PCF is its own filter: no blur (the paper blurs SSAO only)
        break;
      case Effect::Ssgi: {
        ImageF direct;
        stage(timedName(Timed::Direct, l), [&] { direct = directLight(lr.gbuffer, f.shadowMap, f.view, scene_.light, c.ssm.biasTexels); });
        stage(stageName(Part::Raw, l), [&] { lr.raw = renderSsgi(lr.gbuffer, direct, lr.masks.stencil, f.view, lc, c.ssgi); });
        lr.sub = lr.raw;
        break;
      }
    }
  }

  void refineMasks(FrameResult& f, int l) override {
    const Constants& c = f.constants;
    const int next = c.nextCoarserEnabled(l);
    const LevelResult& coarser = f.levels[static_cast<size_t>(next)];
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    Masks marks;  // level l's marks alone, so that SPEC §13's limit clears them as it cleared M_l
    marks[static_cast<size_t>(l)].mask =
        refinementMarks(coarser.sub, coarser.masks.stencil, coarser.gbuffer.hit, 1 << (next - l), lr.masks.mask.width,
                        lr.masks.mask.height, c.effectMask.posterior);
    if (!f.levelLimit.empty()) applyLevelLimit(marks, f.levelLimit, c);
    mrr::refineMasks(lr.masks, marks[static_cast<size_t>(l)].mask, c.levels[static_cast<size_t>(l)]);
    lr.marks = std::move(marks[static_cast<size_t>(l)].mask);
  }

  void blend(FrameResult& f) override {
    const Constants& c = f.constants;
    if (isPeer(c.mode)) {
      std::array<const GBuffer*, kLevelCount> gbuffers{};
      for (size_t l = 0; l < gbuffers.size(); ++l)
        if (c.levels[l].enabled) gbuffers[l] = &f.levels[l].gbuffer;
      f.blend = composePeer(f.blendInputs(), gbuffers, f.tileRates, c, options_.keepStages);
    } else {
      f.blend = blendLevels(f.blendInputs(), c, options_.keepStages);
    }
  }
  void shade(FrameResult& f) override {
    f.shaded = shadeFinal(f.levels[0].gbuffer, f.blend.final, f.shadowLit, f.view, scene_.light, f.constants.effect);
  }

 private:
  const Scene& scene_;
  const RayScene& rays_;
  std::array<OccluderPlanes, kLevelCount>& planes_;
  const RenderOptions& options_;
};
}  // namespace

FrameResult Renderer::render(const Camera& camera, const Constants& constants, const RenderOptions& options) const {
  OracleFrame backend(scene_, rays_, planes_, options);
  return renderFrame(backend, scene_.light, camera, constants, options);
}

}  // namespace mrr
