#include "gpu/pipeline.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <chrono>

#include "common/error.h"
#include "cpu_ref/shade.h"
#include "gpu/bilateral.h"
#include "gpu/blend.h"
#include "gpu/edges.h"
#include "gpu/masks.h"
#include "gpu/shadowmap.h"
#include "gpu/ssao.h"
#include "gpu/ssgi.h"
#include "gpu/ssm.h"

namespace mrr::gpu {

GpuRenderer::GpuRenderer(const Scene& scene, int deviceIndex)
    : scene_(scene), context_(deviceIndex), gpuScene_(scene) {}

FrameResult GpuRenderer::render(const Camera& camera, const Constants& c, const RenderOptions& options) const {
  using Clock = std::chrono::steady_clock;
  require(!isPeer(c.mode), "--path gpu --method " + toString(c.mode) + ": the port does not run the peers yet");
  FrameResult f;
  f.constants = c;
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
  // 1. G-buffers, rasterised per level; the targets stay on the GPU for the later passes.
  std::array<std::unique_ptr<Framebuffer>, kLevelCount> gbuffers;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    stage("gbuffer.L" + std::to_string(l), [&] {
      gbuffers[static_cast<size_t>(l)] = std::make_unique<Framebuffer>(lc.width, lc.height, 3, true);
      drawGBuffer(gpuScene_, f.view, lc, *gbuffers[static_cast<size_t>(l)]);
      f.levels[static_cast<size_t>(l)].gbuffer = readGBuffer(*gbuffers[static_cast<size_t>(l)]);
    });
  }
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
  // 2–3. Edges, masks, stencils; `full` shades every pixel.
  std::array<MaskLevel, kLevelCount> masks;
  if (c.mode == Mode::Multires) {
    const unsigned shadowEdges = c.effect == Effect::Ssm ? shadowTest->texture(0) : 0;
    stage("edges", [&] { f.edges = detectEdges(gpuScene_, *gbuffers[0], c.edges, shadowEdges); });
    stage("masks", [&] { masks = buildMasks(gpuScene_, f.edges.combined, c); });
  } else {
    masks = fullModeMasks(c);
  }
  for (int l = 0; l < kLevelCount; ++l) f.levels[static_cast<size_t>(l)].masks = std::move(masks[static_cast<size_t>(l)]);
  // 4–5. The effect with the stencil test; SSAO then gets the bilateral blur.
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    const Framebuffer& gbuffer = *gbuffers[static_cast<size_t>(l)];
    const std::string L = ".L" + std::to_string(l);
    switch (c.effect) {
      case Effect::Ssao:
        stage("effect" + L, [&] { lr.raw = renderSsao(gpuScene_, gbuffer, lr.masks.stencil, f.view, lc, c.ssao); });
        stage("bilateral" + L,
              [&] { lr.sub = bilateralBlur(gpuScene_, lr.raw, lr.masks.stencil, gbuffer, c.bilateral); });
        break;
      case Effect::Ssm:
        stage("effect" + L, [&] {
          lr.raw =
              renderSsm(gpuScene_, gbuffer, lr.masks.stencil, f.shadowMap, shadowMap->texture(), f.view, lc, c.ssm);
        });
        lr.sub = lr.raw;  // PCF is its own filter: no blur (the paper blurs SSAO only)
        break;
      case Effect::Ssgi: {
        Framebuffer direct(lc.width, lc.height, 1, false);
        stage("direct" + L, [&] {
          drawDirectLight(gpuScene_, gbuffer, f.shadowMap, shadowMap->texture(), f.view, scene_.light, c.ssm.biasTexels,
                          direct);
        });
        stage("effect" + L, [&] {
          lr.raw = renderSsgi(gpuScene_, gbuffer, direct.texture(0), lr.masks.stencil, f.view, lc, c.ssgi);
        });
        lr.sub = lr.raw;
        break;
      }
    }
  }
  f.countShadedPixels();
  // 6. Upsample and blend, coarse to fine.
  stage("blend", [&] { f.blend = blendLevels(gpuScene_, f.blendInputs(), c); });
  // The shaded image for viewing: the oracle's function on the port's buffers.
  stage("shade", [&] { f.shaded = shadeFinal(f.levels[0].gbuffer, f.blend.final, f.shadowLit, f.view, f.light, c.effect); });
  f.timings.push_back({"total", std::chrono::duration<double, std::milli>(Clock::now() - frameStart).count()});
  return f;
}

}  // namespace mrr::gpu
