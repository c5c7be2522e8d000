#include "gpu/pipeline.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <chrono>
#include <utility>
#include <vector>

#include "common/cost_model.h"
#include "common/error.h"
#include "common/stages.h"
#include "gpu/bilateral.h"
#include "gpu/blend.h"
#include "gpu/edges.h"
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

namespace mrr::gpu {

bool isPortOnlyStage(const std::string& stage) { return stage == "stencils"; }

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

FrameResult GpuRenderer::render(const Camera& camera, const Constants& constants, const RenderOptions& options) const {
  using Clock = std::chrono::steady_clock;
  FrameResult f;
  f.constants = constants;
  const Constants& c = f.constants;  // what every stage reads; the never-slower rule may change it
  f.view = makeView(camera, c.width, c.height, c.paddedWidth, c.paddedHeight);
  f.light = scene_.light;
  // Every stage's images stay on the GPU; the frame reads back S_ℓ (for |S_ℓ| and the
  // never-slower rule, before anything is shaded), the final image and level map, and what
  // the shaded image needs. With keepStages (--stages, probe, compare) every stage is read
  // back too, into the structures the oracle fills.
  const bool keep = options.keepStages;
  const auto frameStart = Clock::now();
  // Timer queries: one per GL stage, read once the frame is done (timings[index] ← query).
  std::vector<std::pair<size_t, unsigned>> queries;
  auto stage = [&](const std::string& name, auto&& body) {
    if (options.progress) options.progress(name);
    if (timerQueries_) {
      unsigned query = 0;
      glGenQueries(1, &query);
      glBeginQuery(GL_TIME_ELAPSED, query);
      body();
      glEndQuery(GL_TIME_ELAPSED);
      queries.emplace_back(f.timings.size(), query);
      f.timings.push_back({name, 0.0});
      return;
    }
    const auto t0 = Clock::now();
    body();
    glFinish();
    f.timings.push_back({name, std::chrono::duration<double, std::milli>(Clock::now() - t0).count()});
  };
  // G-buffers, rasterised per level. A coarse level's albedo is read only by SSGI's direct
  // light (and --stages): the resident frame leaves that target out otherwise.
  std::array<Target, kLevelCount> gbuffers;
  auto gbuffer = [&](int l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const int targets = keep || l == 0 || c.effect == Effect::Ssgi ? 3 : 2;
    stage(stageName(Part::GBuffer, l), [&] {
      gbuffers[static_cast<size_t>(l)] = gpuScene_.target(lc.width, lc.height, targets, true);
      drawGBuffer(gpuScene_, f.view, lc, *gbuffers[static_cast<size_t>(l)]);
      if (keep) f.levels[static_cast<size_t>(l)].gbuffer = readGBuffer(*gbuffers[static_cast<size_t>(l)]);
    });
  };

  // 1. The full-res G-buffer (SPEC §1): the masks are made from it alone.
  gbuffer(0);

  // The light's shadow map, and its one-tap test at full res (SPEC §2 shadow edges, §6).
  std::unique_ptr<ShadowMapTarget> shadowMap;
  Target shadowTest;
  if (c.needsShadowMap()) {
    stage(stageName(Part::ShadowMap), [&] {
      f.shadowMap = shadowMapFrame(scene_.light, gpuScene_.bounds(), c.ssm.shadowMapSize);
      shadowMap = std::make_unique<ShadowMapTarget>(c.ssm.shadowMapSize);
      drawShadowMap(gpuScene_, f.shadowMap, *shadowMap);
      if (keep) f.shadowMap.depth = shadowMap->read();
    });
    stage(stageName(Part::ShadowTest), [&] {
      shadowTest = gpuScene_.target(gbuffers[0]->width(), gbuffers[0]->height(), 1, false, Texel::R8);
      drawShadowTest(gpuScene_, *gbuffers[0], f.shadowMap, shadowMap->texture(), f.view, c.ssm.biasTexels, *shadowTest);
      if (keep) f.shadowLit = readShadowTest(*shadowTest);
    });
  }

  // 2–3. Which pixels of which level are shaded (SPEC §2–3; the peers' §9).
  Target edges;
  if (c.mode == Mode::Mrr || c.mode == Mode::Tiles) {
    const unsigned shadowEdges = c.effect == Effect::Ssm ? shadowTest->texture(0) : 0;
    stage(stageName(Part::Edges), [&] {
      edges = drawEdges(gpuScene_, *gbuffers[0], c.edges, shadowEdges, !keep);
      if (keep) f.edges = readEdges(*edges);
    });
  }
  std::array<MaskLevel, kLevelCount> masks;
  std::unique_ptr<MaskTargets> maskTargets;
  switch (c.mode) {
    case Mode::Mrr:
      stage(stageName(Part::Stencil), [&] {
        maskTargets = drawMasks(gpuScene_, edges->texture(0), edgeChannel(!keep), c);
        masks = readMasks(*maskTargets, c, !keep);
        if (keep) masks[0].mask = f.edges.combined;  // M_0 = E
      });
      break;
    case Mode::Tiles:
      stage(stageName(Part::Stencil), [&] {
        f.tileRates = tileRates(gpuScene_, edges->texture(0), edgeChannel(!keep), edges->width(), edges->height());
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
  // The level-0 G-buffer time tells the per-scene part of a rasterised G-buffer, but only on a
  // warm renderer: its first frame also pays shader compilation and fresh targets there.
  applyNeverSlower(f, masks, options.costModel ? *options.costModel : CostModel::defaults("gpu"),
                   framesRendered_ > 0 ? f.timing("gbuffer.L0") : 0.0);
  if (!maskTargets || !maskTargets->drawn || f.fallback.fellBack)  // host stencils: to the GPU
    stage("stencils", [&] { maskTargets = uploadMasks(masks, c); });
  for (int l = 0; l < kLevelCount; ++l) f.levels[static_cast<size_t>(l)].masks = std::move(masks[static_cast<size_t>(l)]);
  f.countShadedPixels();

  // 1, continued. The coarser levels' G-buffers.
  for (int l = 1; l < kLevelCount; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled) gbuffer(l);

  // 4. Sub-images: the effect with the stencil test; SSAO then gets the bilateral blur.
  std::array<Target, kLevelCount> raw, sub;
  std::array<unsigned, kLevelCount> subTexture{};
  TextureSet unshaded;  // uniform-k's level 0: a G-buffer, nothing shaded (c_0 = 0)
  for (int l = 0; l < kLevelCount; ++l) {
    const size_t i = static_cast<size_t>(l);
    const LevelConstants& lc = c.levels[i];
    if (!lc.enabled) continue;
    if (!lc.shaded) {
      const ImageF zero(lc.width, lc.height, c.channels());
      subTexture[i] = unshaded.add(uploadTexture(zero));
      if (keep) f.levels[i].raw = f.levels[i].sub = zero;
      continue;
    }
    const Framebuffer& targets = *gbuffers[i];
    const unsigned stencil = maskTargets->stencil[i];
    // drawn masks know where S_ℓ can be set: the stencil fill covers those rectangles alone
    const std::vector<glm::ivec4>* fill =
        maskTargets->drawn && !maskTargets->supportRects[i].empty() ? &maskTargets->supportRects[i] : nullptr;
    const std::string L = ".L" + std::to_string(l);
    switch (c.effect) {
      case Effect::Ssao:
        stage(stageName(Part::Raw, l), [&] { raw[i] = drawSsao(gpuScene_, targets, stencil, f.view, lc, c.ssao, fill); });
        stage(stageName(Part::Sub, l), [&] { sub[i] = drawBilateral(gpuScene_, raw[i]->texture(0), stencil, targets, c.bilateral, raw[i].get()); });
        break;
      case Effect::Ssm:  // PCF is its own filter: no blur (the paper blurs SSAO only)
        stage(stageName(Part::Raw, l), [&] {
          raw[i] = drawSsm(gpuScene_, targets, stencil, f.shadowMap, shadowMap->texture(), f.view, c.ssm, fill);
        });
        break;
      case Effect::Ssgi: {
        const Target direct = gpuScene_.target(lc.width, lc.height, 1, false);
        stage("direct" + L, [&] {
          drawDirectLight(gpuScene_, targets, f.shadowMap, shadowMap->texture(), f.view, scene_.light, c.ssm.biasTexels,
                          *direct);
        });
        stage(stageName(Part::Raw, l), [&] {
          raw[i] = drawSsgi(gpuScene_, targets, direct->texture(0), stencil, f.view, lc, c.ssgi, fill);
        });
        break;
      }
    }
    const Framebuffer& result = sub[i] ? *sub[i] : *raw[i];
    subTexture[i] = result.texture(0);
    if (keep) {
      f.levels[i].raw = raw[i]->read(0, c.channels());
      f.levels[i].sub = result.read(0, c.channels());
    }
  }

  // 5. Upsample and blend, coarse to fine (SPEC §5); the peers compose their own way (§9).
  GpuImage finalOnGpu;  // for the shaded image
  if (isPeer(c.mode)) {
    std::array<const Framebuffer*, kLevelCount> targets{};
    for (size_t l = 0; l < targets.size(); ++l)
      if (c.levels[l].enabled) targets[l] = gbuffers[l].get();
    stage(stageName(Part::Final), [&] {
      f.blend = composePeer(gpuScene_, subTexture, c.channels(), targets, f.tileRates, c, options.keepStages, &finalOnGpu);
    });
  } else {
    std::array<LevelTextures, kLevelCount> inputs;
    for (size_t l = 0; l < inputs.size(); ++l) inputs[l] = {subTexture[l], maskTargets->stencil[l], maskTargets->alpha[l]};
    const ImageU8* edgeBlocks = maskTargets->drawn ? &maskTargets->edgeBlocks : nullptr;
    stage(stageName(Part::Final), [&] {
      f.blend = blendLevels(gpuScene_, inputs, c.channels(), c, options.keepStages, edgeBlocks, &finalOnGpu);
    });
  }
  // 6. The shaded image for viewing (shade.frag), from the level-0 G-buffer and the final image
  // on the GPU: the same for every method, and no part of the effect's cost.
  stage(stageName(Part::Shaded), [&] {
    f.shaded = drawShade(gpuScene_, *gbuffers[0], finalOnGpu.texture(), shadowTest ? shadowTest->texture(0) : 0, f.view,
                         f.light, c);
  });
  ++framesRendered_;
  glFinish();
  f.timings.push_back({"total", std::chrono::duration<double, std::milli>(Clock::now() - frameStart).count()});
  for (const auto& [index, query] : queries) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    f.timings[index].ms = static_cast<double>(ns) * 1e-6;
    glDeleteQueries(1, &query);
  }
  checkGl("timer queries");
  return f;
}

}  // namespace mrr::gpu
