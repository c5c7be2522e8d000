#include "gpu/pipeline.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <chrono>

#include "common/cost_model.h"
#include "cpu_ref/shade.h"
#include "gpu/bilateral.h"
#include "gpu/blend.h"
#include "gpu/edges.h"
#include "gpu/masks.h"
#include "gpu/peers.h"
#include "gpu/shadowmap.h"
#include "gpu/ssao.h"
#include "gpu/ssgi.h"
#include "gpu/ssm.h"

namespace mrr::gpu {

GpuRenderer::GpuRenderer(const Scene& scene, int deviceIndex)
    : scene_(scene), context_(deviceIndex), gpuScene_(scene) {}

FrameResult GpuRenderer::render(const Camera& camera, const Constants& constants, const RenderOptions& options) const {
  using Clock = std::chrono::steady_clock;
  FrameResult f;
  f.constants = constants;
  const Constants& c = f.constants;  // what every stage reads; the never-slower rule may change it
  f.view = makeView(camera, c.width, c.height, c.paddedWidth, c.paddedHeight);
  f.light = scene_.light;
  const auto frameStart = Clock::now();
  auto stage = [&](const std::string& name, auto&& body) {
    if (options.progress) options.progress(name);
    const auto t0 = Clock::now();
    body();
    glFinish();
    f.timings.push_back({name, std::chrono::duration<double, std::milli>(Clock::now() - t0).count()});
  };
  // G-buffers, rasterised per level; the targets stay on the GPU for the later passes.
  std::array<std::unique_ptr<Framebuffer>, kLevelCount> gbuffers;
  auto gbuffer = [&](int l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    stage("gbuffer.L" + std::to_string(l), [&] {
      gbuffers[static_cast<size_t>(l)] = std::make_unique<Framebuffer>(lc.width, lc.height, 3, true);
      drawGBuffer(gpuScene_, f.view, lc, *gbuffers[static_cast<size_t>(l)]);
      f.levels[static_cast<size_t>(l)].gbuffer = readGBuffer(*gbuffers[static_cast<size_t>(l)]);
    });
  };

  // 1. The full-res G-buffer (SPEC §1): the masks are made from it alone.
  gbuffer(0);

  // The light's shadow map, and its one-tap test at full res (SPEC §2 shadow edges, §6); both
  // stay on the GPU for the later passes and are read back for --stages and probe.
  std::unique_ptr<ShadowMapTarget> shadowMap;
  std::unique_ptr<Framebuffer> shadowTest;
  if (c.needsShadowMap()) {
    stage("shadowmap", [&] {
      f.shadowMap = shadowMapFrame(scene_.light, gpuScene_.bounds(), c.ssm.shadowMapSize);
      shadowMap = std::make_unique<ShadowMapTarget>(c.ssm.shadowMapSize);
      drawShadowMap(gpuScene_, f.shadowMap, *shadowMap);
      f.shadowMap.depth = shadowMap->read();
    });
    stage("shadowtest", [&] {
      shadowTest = std::make_unique<Framebuffer>(gbuffers[0]->width(), gbuffers[0]->height(), 1, false);
      drawShadowTest(gpuScene_, *gbuffers[0], f.shadowMap, shadowMap->texture(), f.view, c.ssm.biasTexels, *shadowTest);
      f.shadowLit = readShadowTest(*shadowTest);
    });
  }

  // 2–3. Which pixels of which level are shaded (SPEC §2–3; the peers' §9).
  std::array<MaskLevel, kLevelCount> masks;
  if (c.mode == Mode::Multires || c.mode == Mode::Tiles) {
    const unsigned shadowEdges = c.effect == Effect::Ssm ? shadowTest->texture(0) : 0;
    stage("edges", [&] { f.edges = detectEdges(gpuScene_, *gbuffers[0], c.edges, shadowEdges); });
  }
  switch (c.mode) {
    case Mode::Multires: stage("masks", [&] { masks = buildMasks(gpuScene_, f.edges.combined, c); }); break;
    case Mode::Tiles:
      stage("masks", [&] {
        f.tileRates = tileRates(gpuScene_, f.edges.combined);
        masks = tileMasks(gpuScene_, f.tileRates, c);
      });
      break;
    // uniform-k's stencil is a constant of the frame's size (every level-k pixel inside W×H):
    // the oracle's own function, as `full` below; there is no image to compute it from.
    case Mode::Uniform1:
    case Mode::Uniform2: masks = uniformMasks(c); break;
    case Mode::Full: masks = fullModeMasks(c); break;
  }
  // SPEC §11: with the stencils known and nothing shaded yet, predict both frames' rest.
  applyNeverSlower(f, masks, options.costModel ? *options.costModel : CostModel::defaults("gpu"));
  for (int l = 0; l < kLevelCount; ++l) f.levels[static_cast<size_t>(l)].masks = std::move(masks[static_cast<size_t>(l)]);

  // 1, continued. The coarser levels' G-buffers.
  for (int l = 1; l < kLevelCount; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled) gbuffer(l);

  // 4. Sub-images: the effect with the stencil test; SSAO then gets the bilateral blur.
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    if (!lc.shaded) {  // uniform-k's level 0: a G-buffer, nothing shaded
      lr.raw = lr.sub = ImageF(lc.width, lc.height, c.channels());
      continue;
    }
    const Framebuffer& targets = *gbuffers[static_cast<size_t>(l)];
    const std::string L = ".L" + std::to_string(l);
    switch (c.effect) {
      case Effect::Ssao:
        stage("effect" + L, [&] { lr.raw = renderSsao(gpuScene_, targets, lr.masks.stencil, f.view, lc, c.ssao); });
        stage("bilateral" + L,
              [&] { lr.sub = bilateralBlur(gpuScene_, lr.raw, lr.masks.stencil, targets, c.bilateral); });
        break;
      case Effect::Ssm:
        stage("effect" + L, [&] {
          lr.raw =
              renderSsm(gpuScene_, targets, lr.masks.stencil, f.shadowMap, shadowMap->texture(), f.view, lc, c.ssm);
        });
        lr.sub = lr.raw;  // PCF is its own filter: no blur (the paper blurs SSAO only)
        break;
      case Effect::Ssgi: {
        Framebuffer direct(lc.width, lc.height, 1, false);
        stage("direct" + L, [&] {
          drawDirectLight(gpuScene_, targets, f.shadowMap, shadowMap->texture(), f.view, scene_.light, c.ssm.biasTexels,
                          direct);
        });
        stage("effect" + L, [&] {
          lr.raw = renderSsgi(gpuScene_, targets, direct.texture(0), lr.masks.stencil, f.view, lc, c.ssgi);
        });
        lr.sub = lr.raw;
        break;
      }
    }
  }
  f.countShadedPixels();

  // 5. Upsample and blend, coarse to fine (SPEC §5); the peers compose their own way (§9).
  if (isPeer(c.mode)) {
    std::array<const Framebuffer*, kLevelCount> targets{};
    for (size_t l = 0; l < targets.size(); ++l)
      if (c.levels[l].enabled) targets[l] = gbuffers[l].get();
    stage("blend", [&] {
      f.blend = composePeer(gpuScene_, f.blendInputs(), targets, f.tileRates, c, options.keepStages);
    });
  } else {
    stage("blend", [&] { f.blend = blendLevels(gpuScene_, f.blendInputs(), c, options.keepStages); });
  }
  // 6. The shaded image for viewing: the oracle's function on the port's buffers.
  stage("shade", [&] { f.shaded = shadeFinal(f.levels[0].gbuffer, f.blend.final, f.shadowLit, f.view, f.light, c.effect); });
  f.timings.push_back({"total", std::chrono::duration<double, std::milli>(Clock::now() - frameStart).count()});
  return f;
}

}  // namespace mrr::gpu
