#include "cpu_ref/oracle.h"

#include <array>
#include <cmath>
#include <string>

#include "common/stages.h"
#include "cpu_ref/bilateral.h"
#include "cpu_ref/blend.h"
#include "cpu_ref/edges.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/peers.h"
#include "cpu_ref/shade.h"
#include "cpu_ref/shadowmap.h"
#include "cpu_ref/ssao.h"
#include "cpu_ref/ssgi.h"
#include "cpu_ref/ssm.h"
#include "cpu_ref/temporal.h"

namespace mrr {

// Scratch reused across frames, so a steady stream of frames does not page-fault it in again
// each time (the stages are therefore not re-entrant on one object).
struct OracleScratch {
  std::array<OccluderPlanes, kLevelCount> planes;
};

OracleStages::OracleStages(const DirectionalLight& light, const RayScene* rays)
    : light_(light), rays_(rays), scratch_(std::make_unique<OracleScratch>()) {}
OracleStages::~OracleStages() = default;

namespace {
const RayScene& needRays(const RayScene* rays, const char* stage) {
  require(rays != nullptr, std::string("internal: the oracle's ") + stage + " casts rays, and these stages have no scene BVH");
  return *rays;
}
const ImageU8* shadowEdgesOf(const FrameResult& in) {
  return in.constants.effect == Effect::Ssm ? &in.shadowLit : nullptr;  // SPEC §2: SSM's shadow edges
}
const ImageU8* limitOf(const FrameResult& in) { return in.levelLimit.empty() ? nullptr : &in.levelLimit; }
}  // namespace

// ---- 1. G-buffers, the shadow map and its test, the rule's samples ----------------------------

GBuffer OracleStages::gbuffer(const View& view, const LevelConstants& level) const {
  return renderGBuffer(needRays(rays_, "G-buffer"), view, level);
}

GBuffer OracleStages::coarseGBuffer(const FrameResult& in, int l) const {
  const LevelConstants& level = in.constants.levels[static_cast<size_t>(l)];
  // SPEC §1: --coarse-gbuffer render casts a ray at each level pixel's centre ((x+½)s, (y+½)s)
  return in.constants.renderCoarseGBuffer ? gbuffer(in.view, level) : subsampleGBuffer(in.levels[0].gbuffer, level);
}

ShadowMap OracleStages::shadowMap(const Constants& c) const {
  const RayScene& rays = needRays(rays_, "shadow map");
  return renderShadowMap(rays, light_, rays.scene().bounds(), c.ssm.shadowMapSize);
}

ImageU8 OracleStages::shadowTest(const FrameResult& in) const {
  return shadowTestImage(in.levels[0].gbuffer, in.shadowMap, in.view, in.constants.ssm.biasTexels);
}

ImageU8 OracleStages::pcfSample(const FrameResult& in) const {
  return mrr::pcfSample(in.levels[0].gbuffer, in.shadowMap, in.view, in.constants.ssm);
}

ImageU8 OracleStages::edgeSample(const FrameResult& in) const {
  return mrr::edgeSample(in.levels[0].gbuffer, in.constants.edges, shadowEdgesOf(in));
}

// ---- 2. Edges ---------------------------------------------------------------------------------

EdgeImages OracleStages::edges(const FrameResult& in) const {
  return detectEdges(in.levels[0].gbuffer, in.constants.edges, shadowEdgesOf(in));
}

std::vector<char> OracleStages::edgeGuardBand(const FrameResult& in, float bandWidth) const {
  const GBuffer& g = in.levels[0].gbuffer;
  const EdgeSettings& s = in.constants.edges;
  std::vector<char> band(static_cast<size_t>(g.width) * static_cast<size_t>(g.height), 0);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const EdgeDecision e = edgeAt(g, s, x, y);
      const float depth = std::max(e.depthSecondX, e.depthSecondY);
      band[static_cast<size_t>(y) * static_cast<size_t>(g.width) + static_cast<size_t>(x)] =
          std::fabs(e.normalMax - s.normalThreshold) <= bandWidth * s.normalThreshold ||
          std::fabs(depth - s.depthThreshold) <= bandWidth * s.depthThreshold;
    }
  return band;
}

// ---- 3. Masks ---------------------------------------------------------------------------------

LevelLimit OracleStages::levelLimit(const FrameResult& in) const {
  return mrr::levelLimit(in.levels[0].gbuffer, in.view, in.constants);
}

ImageF OracleStages::footprint(const FrameResult& in) const {
  const Constants& c = in.constants;
  return effectFootprint(in.levels[0].gbuffer, in.edges.combined, in.view, c.needsShadowMap() ? &in.shadowMap : nullptr, c);
}

MaskStages OracleStages::maskStages(const FrameResult& in, const ImageF* footprint) const {
  return mrr::maskStages(in.edges.combined, in.constants, footprint);
}

Masks OracleStages::edgeMasks(const FrameResult& in) const {
  return buildMasks(in.edges.combined, in.constants, nullptr, limitOf(in));
}

Masks OracleStages::effectMasks(const FrameResult& in, const ImageF* footprint) const {
  // SPEC §12: the effect's footprint at the edges, then the paper's masks from the widened M_ℓ.
  if (footprint) return buildMasks(in.edges.combined, in.constants, footprint, limitOf(in));
  const ImageF made = this->footprint(in);
  return buildMasks(in.edges.combined, in.constants, &made, limitOf(in));
}

ImageU8 OracleStages::tileRates(const FrameResult& in) const {
  ImageU8 rates = mrr::tileRates(in.edges.combined);
  if (const ImageU8* limit = limitOf(in)) limitTileRates(rates, *limit);  // SPEC §13
  return rates;
}

Masks OracleStages::tileMasks(const FrameResult& in, ImageU8& rates) const {
  rates = tileRates(in);
  return mrr::tileMasks(rates, in.constants);
}

Masks OracleStages::tileStencils(const FrameResult& in) const { return mrr::tileMasks(in.tileRates, in.constants); }

Masks OracleStages::masks(const FrameResult& in, ImageU8* rates) const {
  return masks(in, methodInfo(in.constants.mode).masks, rates);
}

Masks OracleStages::masks(const FrameResult& in, MaskBuilder builder, ImageU8* rates) const {
  switch (builder) {
    case MaskBuilder::Full: return fullModeMasks(in.constants);
    case MaskBuilder::Uniform: return uniformMasks(in.constants);
    case MaskBuilder::Tiles: {
      ImageU8 made;
      Masks m = tileMasks(in, made);
      if (rates) *rates = std::move(made);
      return m;
    }
    case MaskBuilder::Edges: return edgeMasks(in);
    case MaskBuilder::EffectEdges: return effectMasks(in);
  }
  return {};
}

ImageU8 OracleStages::marks(const FrameResult& in, int l, RefinementSelection* selection) const {
  const Constants& c = in.constants;
  const int next = c.nextCoarserEnabled(l);
  const LevelResult& coarser = in.levels[static_cast<size_t>(next)];
  const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
  const RefinementRecord& budget = in.refinement[static_cast<size_t>(l)];
  // 1. which coarser pixels vary: v(q) > τ_v, or with a budget the selection (SPEC §12.4)
  const ImageF range = localRangesSeparable(coarser.sub, coarser.masks.stencil, coarser.gbuffer.hit);
  ImageU8 varies;
  if (budget.budgeted) {
    // the prices from the a-priori S_ℓ: made here before the refinement, or the frame's own (kept)
    std::vector<uint32_t> prices = !budget.candidatePrices.empty()
                                       ? budget.candidatePrices
                                       : candidatePrices(in.levels[static_cast<size_t>(l)].masks.stencil,
                                                         in.levels[0].gbuffer.hit, in.pcfSample, c, l, next, budget.units);
    RefinementSelection chosen =
        selectRefinement(range, prices, levelShare(budget.leftUnits, budget.levelsLeft), c.effectMask.posterior,
                         c.effectMask.hysteresis, budget.previousMarked.empty() ? nullptr : &budget.previousMarked);
    chosen.prices = std::move(prices);
    varies = chosen.varies;
    if (selection) *selection = std::move(chosen);
  } else {
    varies = variesAbove(range, c.effectMask.posterior);
  }
  Masks marks;  // level ℓ's marks alone, so that SPEC §13's limit clears them as it cleared M_ℓ
  // 2. each finer pixel takes its parent's mark
  marks[static_cast<size_t>(l)].mask = parentMarks(varies, 1 << (next - l), lc.width, lc.height);
  if (const ImageU8* limit = limitOf(in)) applyLevelLimit(marks, *limit, c);
  return std::move(marks[static_cast<size_t>(l)].mask);
}

void OracleStages::refine(MaskLevel& level, const ImageU8& marks, const LevelConstants& lc) const {
  refineMasks(level, marks, lc);
}

// ---- 4. The effect ----------------------------------------------------------------------------

ImageF OracleStages::raw(const FrameResult& in, int l, const StageFn& stage, const ProgressFn& progress) const {
  const Constants& c = in.constants;
  const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
  const LevelResult& lr = in.levels[static_cast<size_t>(l)];
  const auto run = [&](Timed t, const std::function<void()>& body) {
    if (stage) stage(timedName(t, l), body);
    else body();
  };
  ImageF out;
  switch (c.effect) {
    case Effect::Ssao: {
      OccluderPlanes& planes = scratch_->planes[static_cast<size_t>(l)];
      run(Timed::Planes, [&] { occluderPlanes(lr.gbuffer, planes); });
      // Long levels (over ~2·10⁸ samples, seconds on 2 cores) also report their tenths.
      std::function<void(double)> tenths;
      const double work = static_cast<double>(lc.width) * lc.height * c.ssao.samples;
      if (progress && work > 2e8)
        tenths = [&](double done) {
          progress(stageName(Part::Raw, l) + " " + std::to_string(static_cast<int>(done * 100 + 0.5)) + "%");
        };
      run(Timed::Effect, [&] { out = renderSsao(lr.gbuffer, planes, lr.masks.stencil, in.view, lc, c.ssao, tenths); });
      break;
    }
    case Effect::Ssm:
      run(Timed::Effect, [&] { out = renderSsm(lr.gbuffer, in.shadowMap, lr.masks.stencil, in.view, c.ssm); });
      break;
    case Effect::Ssgi: {
      ImageF direct;
      run(Timed::Direct, [&] { direct = directLight(lr.gbuffer, in.shadowMap, in.view, light_, c.ssm.biasTexels); });
      run(Timed::Effect, [&] { out = renderSsgi(lr.gbuffer, direct, lr.masks.stencil, in.view, lc, c.ssgi); });
      break;
    }
  }
  return out;
}

ImageF OracleStages::sub(const FrameResult& in, int l, const ImageF& raw) const {
  const LevelResult& lr = in.levels[static_cast<size_t>(l)];
  // PCF is its own filter, and SSGI's senders average: the paper blurs SSAO only (SPEC §4).
  if (in.constants.effect != Effect::Ssao) return raw;
  return bilateralBlur(raw, lr.masks.stencil, lr.gbuffer, in.constants.bilateral);
}

// ---- 5. Blend ---------------------------------------------------------------------------------

namespace {
std::array<const GBuffer*, kLevelCount> gbuffersOf(const FrameResult& in) {
  std::array<const GBuffer*, kLevelCount> gbuffers{};
  for (size_t l = 0; l < gbuffers.size(); ++l)
    if (in.constants.levels[l].enabled) gbuffers[l] = &in.levels[l].gbuffer;
  return gbuffers;
}
}  // namespace

BlendResult OracleStages::blend(const FrameResult& in, bool keepStages) const {
  const Constants& c = in.constants;
  if (methodInfo(c.mode).peer()) return composePeer(in.blendInputs(), gbuffersOf(in), in.tileRates, c, keepStages);
  return blendLevels(in.blendInputs(), c, keepStages);
}

BlendResult OracleStages::blendStepwise(const FrameResult& in) const {
  const Constants& c = in.constants;
  if (methodInfo(c.mode).peer()) {
    bool kept = false;
    for (size_t l = 0; l < kLevelCount; ++l) kept = kept || !in.blend.upsampled[l].data.empty();
    return composePeer(in.blendInputs(), gbuffersOf(in), in.tileRates, c, kept);
  }
  BlendResult out;
  const int w = c.width, h = c.height;
  int coarser = -1;
  for (int l = kLevelCount - 1; l >= 0; --l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const size_t i = static_cast<size_t>(l);
    const LevelResult& lr = in.levels[i];
    if (in.blend.upsampled[i].data.empty()) continue;  // rendered without keepStages
    const int ch = in.blend.upsampled[i].channels;
    ImageF up(w, h, ch), alpha(w, h, 1), composite(w, h, ch);
    const bool coarsest = coarser < 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Upsampled u = upsampleAt(lr.sub, lr.masks.stencil, lr.masks.alpha, lc, x, y);
        alpha.at(x, y) = coarsest ? (u.covered ? 1.0f : 0.0f) : u.alpha;
        for (int k = 0; k < ch; ++k) {
          up.at(x, y, k) = u.color[k];
          const float hat = in.blend.upsampled[i].at(x, y, k);
          composite.at(x, y, k) =
              coarsest ? hat : blendStep(in.blend.alpha[i].at(x, y), hat, in.blend.composite[static_cast<size_t>(coarser)].at(x, y, k));
        }
      }
    out.upsampled[i] = std::move(up);
    out.alpha[i] = std::move(alpha);
    out.composite[i] = std::move(composite);
    coarser = l;
  }
  if (coarser >= 0) out.final = in.blend.composite[static_cast<size_t>(coarser)];  // the finest composite is the final image
  return out;
}

// ---- §14. The temporal term ----------------------------------------------------------------

TemporalImages OracleStages::temporal(const FrameResult& in, const FrameHistory& history) const {
  const Constants& c = in.constants;
  require(history.result.width == c.width && history.result.height == c.height &&
              history.result.channels == in.blend.final.channels,
          "the temporal term: the previous frame is " + std::to_string(history.result.width) + "x" +
              std::to_string(history.result.height) + ", this one " + std::to_string(c.width) + "x" + std::to_string(c.height));
  return temporalTerm(in, in.blend.final, history);
}

// ---- 6. The shaded image ----------------------------------------------------------------------

ImageF OracleStages::shaded(const FrameResult& in) const {
  return shadeFinal(in.levels[0].gbuffer, in.final(), in.shadowLit, in.view, light_, in.constants.effect);
}

}  // namespace mrr
