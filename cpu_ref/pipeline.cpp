#include "cpu_ref/pipeline.h"

#include <chrono>
#include <vector>

#include "common/parallel.h"
#include "common/stages.h"
#include "cpu_ref/bilateral.h"
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

FrameResult Renderer::render(const Camera& camera, const Constants& constants, const RenderOptions& options) const {
  const ProgressFn& progress = options.progress;
  FrameResult f;
  f.constants = constants;
  const Constants& c = f.constants;  // what every stage reads; the never-slower rule may change it
  f.view = makeView(camera, c.width, c.height, c.paddedWidth, c.paddedHeight);
  f.light = scene_.light;
  const auto frameStart = Clock::now();
  auto stage = [&](const std::string& name, auto&& body) {
    if (progress) progress(name);
    const auto t0 = Clock::now();
    body();
    f.timings.push_back({name, msSince(t0)});
  };
  auto gbuffer = [&](int l) {
    stage(stageName(Part::GBuffer, l),
          [&] { f.levels[static_cast<size_t>(l)].gbuffer = renderGBuffer(rays_, f.view, c.levels[static_cast<size_t>(l)]); });
  };

  // 1. The full-res G-buffer (SPEC §1): the masks are made from it alone.
  gbuffer(0);

  // The light's shadow map, and its one-tap test at full res (SPEC §2 shadow edges, §6).
  if (c.needsShadowMap()) {
    stage(stageName(Part::ShadowMap), [&] { f.shadowMap = renderShadowMap(rays_, scene_.light, scene_.bounds(), c.ssm.shadowMapSize); });
    stage(stageName(Part::ShadowTest), [&] {
      f.shadowLit = shadowTestImage(f.levels[0].gbuffer, f.shadowMap, f.view, c.ssm.biasTexels);
    });
  }

  // 2–3. Which pixels of which level are shaded (SPEC §2–3; the peers' §9).
  std::array<MaskLevel, kLevelCount> masks;
  if (c.mode == Mode::Mrr || c.mode == Mode::Tiles) {
    const ImageU8* shadowEdges = c.effect == Effect::Ssm ? &f.shadowLit : nullptr;
    stage(stageName(Part::Edges), [&] { f.edges = detectEdges(f.levels[0].gbuffer, c.edges, shadowEdges); });
  }
  switch (c.mode) {
    case Mode::Mrr: stage(stageName(Part::Stencil), [&] { masks = buildMasks(f.edges.combined, c); }); break;
    case Mode::Tiles:
      stage(stageName(Part::Stencil), [&] {
        f.tileRates = tileRates(f.edges.combined);
        masks = tileMasks(f.tileRates, c);
      });
      break;
    case Mode::Uniform1:
    case Mode::Uniform2: masks = uniformMasks(c); break;
    case Mode::Full: masks = fullModeMasks(c); break;
  }
  // SPEC §11: with the stencils known and nothing shaded yet, predict both frames' rest.
  applyNeverSlower(f, masks, options.costModel ? *options.costModel : CostModel::defaults("cpu"));
  for (int l = 0; l < kLevelCount; ++l) f.levels[static_cast<size_t>(l)].masks = std::move(masks[static_cast<size_t>(l)]);

  // 1, continued. The coarser levels' G-buffers.
  for (int l = 1; l < kLevelCount; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled) gbuffer(l);

  // 4. Sub-images: the effect at stencilled pixels only, then the bilateral blur (SPEC §4).
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    if (!lc.shaded) {  // uniform-k's level 0: a G-buffer, nothing shaded
      lr.raw = lr.sub = ImageF(lc.width, lc.height, c.channels());
      continue;
    }
    const std::string L = ".L" + std::to_string(l);
    switch (c.effect) {
      case Effect::Ssao: {
        OccluderPlanes& planes = planes_[static_cast<size_t>(l)];
        stage("planes" + L, [&] { occluderPlanes(lr.gbuffer, planes); });
        // Long stages (over ~2·10⁸ samples, seconds on 2 cores) also report their tenths.
        std::function<void(double)> tenths;
        const double work = static_cast<double>(lc.width) * lc.height * c.ssao.samples;
        if (progress && work > 2e8)
          tenths = [&](double done) { progress(stageName(Part::Raw, l) + " " + std::to_string(static_cast<int>(done * 100 + 0.5)) + "%"); };
        stage(stageName(Part::Raw, l), [&] { lr.raw = renderSsao(lr.gbuffer, planes, lr.masks.stencil, f.view, lc, c.ssao, tenths); });
        stage(stageName(Part::Sub, l), [&] { lr.sub = bilateralBlur(lr.raw, lr.masks.stencil, lr.gbuffer, c.bilateral); });
        break;
      }
      case Effect::Ssm:
        stage(stageName(Part::Raw, l), [&] { lr.raw = renderSsm(lr.gbuffer, f.shadowMap, lr.masks.stencil, f.view, c.ssm); });
        lr.sub = lr.raw;  // PCF is its own filter: no blur (the paper blurs SSAO only)
        break;
      case Effect::Ssgi: {
        ImageF direct;
        stage("direct" + L, [&] { direct = directLight(lr.gbuffer, f.shadowMap, f.view, scene_.light, c.ssm.biasTexels); });
        stage(stageName(Part::Raw, l), [&] { lr.raw = renderSsgi(lr.gbuffer, direct, lr.masks.stencil, f.view, lc, c.ssgi); });
        lr.sub = lr.raw;
        break;
      }
    }
  }
  f.countShadedPixels();

  // 5. Upsample and blend, coarse to fine (SPEC §5); the peers compose their own way (§9).
  if (isPeer(c.mode)) {
    std::array<const GBuffer*, kLevelCount> gbuffers{};
    for (size_t l = 0; l < gbuffers.size(); ++l)
      if (c.levels[l].enabled) gbuffers[l] = &f.levels[l].gbuffer;
    stage(stageName(Part::Final), [&] { f.blend = composePeer(f.blendInputs(), gbuffers, f.tileRates, c, options.keepStages); });
  } else {
    stage(stageName(Part::Final), [&] { f.blend = blendLevels(f.blendInputs(), c, options.keepStages); });
  }
  // 6. The shaded image for viewing (SPEC §6).
  stage(stageName(Part::Shaded), [&] {
    f.shaded = shadeFinal(f.levels[0].gbuffer, f.blend.final, f.shadowLit, f.view, scene_.light, c.effect);
  });
  f.timings.push_back({"total", msSince(frameStart)});
  return f;
}

}  // namespace mrr
