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
#include "gpu/ssao.h"

namespace mrr::gpu {

GpuRenderer::GpuRenderer(const Scene& scene, int deviceIndex)
    : scene_(scene), context_(deviceIndex), gpuScene_(scene) {}

FrameResult GpuRenderer::render(const Camera& camera, const Constants& c, const RenderOptions& options) const {
  require(c.effect == Effect::Ssao, "--path gpu: " + toString(c.effect) +
                                        " is not ported yet (ssao is; use --path cpu for ssm and ssgi)");
  using Clock = std::chrono::steady_clock;
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
  // 2–3. Edges, masks, stencils.
  std::array<MaskLevel, kLevelCount> masks;
  if (c.mode == Mode::Multires) {
    stage("edges", [&] { f.edges = detectEdges(gpuScene_, *gbuffers[0], c.edges); });
    stage("masks", [&] { masks = buildMasks(gpuScene_, f.edges.combined, c); });
  } else {
    masks = fullModeMasks(c);
  }
  for (int l = 0; l < kLevelCount; ++l) f.levels[static_cast<size_t>(l)].masks = std::move(masks[static_cast<size_t>(l)]);
  // 4–5. SSAO with the stencil test, then the bilateral blur.
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    const std::string L = ".L" + std::to_string(l);
    stage("effect" + L, [&] { lr.raw = renderSsao(gpuScene_, *gbuffers[static_cast<size_t>(l)], lr.masks.stencil, f.view, lc, c.ssao); });
    stage("bilateral" + L, [&] {
      lr.sub = bilateralBlur(gpuScene_, lr.raw, lr.masks.stencil, *gbuffers[static_cast<size_t>(l)], c.bilateral);
    });
  }
  f.countShadedPixels();
  // 6. Upsample and blend, coarse to fine.
  stage("blend", [&] {
    std::array<LevelImages, kLevelCount> in;
    for (int l = 0; l < kLevelCount; ++l) {
      const LevelResult& lr = f.levels[static_cast<size_t>(l)];
      in[static_cast<size_t>(l)] = {&lr.sub, &lr.masks.stencil, &lr.masks.alpha};
    }
    f.blend = blendLevels(gpuScene_, in, c);
  });
  // The shaded image for viewing: the oracle's function on the port's buffers.
  stage("shade", [&] { f.shaded = shadeFinal(f.levels[0].gbuffer, f.blend.final, f.shadowLit, f.view, f.light, c.effect); });
  f.timings.push_back({"total", std::chrono::duration<double, std::milli>(Clock::now() - frameStart).count()});
  return f;
}

}  // namespace mrr::gpu
