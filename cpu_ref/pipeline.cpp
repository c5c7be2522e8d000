#include "cpu_ref/pipeline.h"

#include <chrono>
#include <vector>

#include "common/parallel.h"
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

void FrameResult::countShadedPixels() {
  shadedPixelsTotal = 0;
  int64_t blockTotal = 0;
  for (int l = 0; l < kLevelCount; ++l) {
    LevelResult& lr = levels[static_cast<size_t>(l)];
    lr.shadedPixels = lr.shadedBlockPixels = 0;
    if (!constants.levels[static_cast<size_t>(l)].enabled) continue;
    const ImageU8& s = lr.masks.stencil;
    // Per pair of rows (one row of 4×2 blocks): its set pixels and its blocks holding any;
    // integer sums, so the total is the same for any thread count.
    const int blockRows = (s.height + 1) / 2;
    std::vector<int64_t> setPixels(static_cast<size_t>(blockRows)), blockPixels(static_cast<size_t>(blockRows));
    parallelFor(0, blockRows, [&](int by) {
      const uint8_t* top = &s.at(0, 2 * by);
      const uint8_t* bottom = 2 * by + 1 < s.height ? &s.at(0, 2 * by + 1) : nullptr;
      int64_t set = 0, blocks = 0;
      for (int bx = 0; bx < s.width; bx += 4) {
        uint8_t any = 0;
        for (int x = bx; x < std::min(bx + 4, s.width); ++x) {
          set += top[x] + (bottom ? bottom[x] : 0);
          any |= top[x] | (bottom ? bottom[x] : 0);
        }
        blocks += any ? 8 : 0;
      }
      setPixels[static_cast<size_t>(by)] = set;
      blockPixels[static_cast<size_t>(by)] = blocks;
    });
    for (int by = 0; by < blockRows; ++by) {
      lr.shadedPixels += setPixels[static_cast<size_t>(by)];
      lr.shadedBlockPixels += blockPixels[static_cast<size_t>(by)];
    }
    shadedPixelsTotal += lr.shadedPixels;
    blockTotal += lr.shadedBlockPixels;
  }
  const double pixels = static_cast<double>(constants.width) * constants.height;
  idealSpeedup = pixels / static_cast<double>(std::max<int64_t>(shadedPixelsTotal, 1));
  blockIdealSpeedup = pixels / static_cast<double>(std::max<int64_t>(blockTotal, 1));
}

std::array<LevelImages, kLevelCount> FrameResult::blendInputs() const {
  std::array<LevelImages, kLevelCount> in;
  for (size_t l = 0; l < in.size(); ++l) in[l] = {&levels[l].sub, &levels[l].masks.stencil, &levels[l].masks.alpha};
  return in;
}

std::array<long long, kLevelCount> shadedPixelCounts(const std::array<MaskLevel, kLevelCount>& masks,
                                                     const Constants& c) {
  std::array<long long, kLevelCount> counts{};
  for (int l = 0; l < kLevelCount; ++l) {
    if (!c.levels[static_cast<size_t>(l)].shaded) continue;
    for (uint8_t v : masks[static_cast<size_t>(l)].stencil.data) counts[static_cast<size_t>(l)] += v;
  }
  return counts;
}

void applyNeverSlower(FrameResult& f, std::array<MaskLevel, kLevelCount>& masks, const CostModel& model,
                      double gbuffer0Ms) {
  if (!f.constants.neverSlower) return;
  f.fallback = decideFallback(model, f.constants, shadedPixelCounts(masks, f.constants), gbuffer0Ms);
  if (!f.fallback.fellBack) return;
  f.constants.fallBackToFull();
  masks = fullModeMasks(f.constants);
}

double FrameResult::timing(const std::string& stage) const {
  double ms = 0.0;
  for (const StageTiming& t : timings)
    if (t.stage == stage) ms += t.ms;
  return ms;
}

int64_t estimateFrameBytes(const Constants& c, bool keepStages) {
  const int64_t channels = c.channels();
  int64_t bytes = 0;
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled) continue;
    const int64_t pixels = static_cast<int64_t>(lc.width) * lc.height;
    int64_t perPixel = 4 + 12 + 12 + 12 + 1;  // G-buffer: depth, position, normal, albedo, hit
    perPixel += 1 + 4 + 1;                    // M_ℓ, a_ℓ, S_ℓ
    perPixel += 2 * 4 * channels;             // raw and blurred sub-image
    if (c.effect == Effect::Ssao) perPixel += 16;  // occluder planes
    if (c.effect == Effect::Ssgi) perPixel += 12;  // direct light
    bytes += pixels * perPixel;
  }
  const int64_t padded = static_cast<int64_t>(c.paddedWidth) * c.paddedHeight;
  const int64_t pixels = static_cast<int64_t>(c.width) * c.height;
  bytes += padded * 5;                          // edge kinds and E
  bytes += pixels * (4 * channels + 1 + 12 + 1);  // final, level map, shaded, one-tap shadow test
  if (keepStages) bytes += pixels * kLevelCount * (8 * channels + 4);  // ĉ_ℓ, c'_ℓ, α_ℓ
  if (c.needsShadowMap()) bytes += static_cast<int64_t>(c.ssm.shadowMapSize) * c.ssm.shadowMapSize * 4;
  bytes += pixels * 12;  // the largest image being written (an 8-bit or float copy of it)
  return bytes;
}

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
    stage("gbuffer.L" + std::to_string(l),
          [&] { f.levels[static_cast<size_t>(l)].gbuffer = renderGBuffer(rays_, f.view, c.levels[static_cast<size_t>(l)]); });
  };

  // 1. The full-res G-buffer (SPEC §1): the masks are made from it alone.
  gbuffer(0);

  // The light's shadow map, and its one-tap test at full res (SPEC §2 shadow edges, §6).
  if (c.needsShadowMap()) {
    stage("shadowmap", [&] { f.shadowMap = renderShadowMap(rays_, scene_.light, scene_.bounds(), c.ssm.shadowMapSize); });
    stage("shadowtest", [&] {
      f.shadowLit = shadowTestImage(f.levels[0].gbuffer, f.shadowMap, f.view, c.ssm.biasTexels);
    });
  }

  // 2–3. Which pixels of which level are shaded (SPEC §2–3; the peers' §9).
  std::array<MaskLevel, kLevelCount> masks;
  if (c.mode == Mode::Multires || c.mode == Mode::Tiles) {
    const ImageU8* shadowEdges = c.effect == Effect::Ssm ? &f.shadowLit : nullptr;
    stage("edges", [&] { f.edges = detectEdges(f.levels[0].gbuffer, c.edges, shadowEdges); });
  }
  switch (c.mode) {
    case Mode::Multires: stage("masks", [&] { masks = buildMasks(f.edges.combined, c); }); break;
    case Mode::Tiles:
      stage("masks", [&] {
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
          tenths = [&](double done) { progress("effect" + L + " " + std::to_string(static_cast<int>(done * 100 + 0.5)) + "%"); };
        stage("effect" + L, [&] { lr.raw = renderSsao(lr.gbuffer, planes, lr.masks.stencil, f.view, lc, c.ssao, tenths); });
        stage("bilateral" + L, [&] { lr.sub = bilateralBlur(lr.raw, lr.masks.stencil, lr.gbuffer, c.bilateral); });
        break;
      }
      case Effect::Ssm:
        stage("effect" + L, [&] { lr.raw = renderSsm(lr.gbuffer, f.shadowMap, lr.masks.stencil, f.view, c.ssm); });
        lr.sub = lr.raw;  // PCF is its own filter: no blur (the paper blurs SSAO only)
        break;
      case Effect::Ssgi: {
        ImageF direct;
        stage("direct" + L, [&] { direct = directLight(lr.gbuffer, f.shadowMap, f.view, scene_.light, c.ssm.biasTexels); });
        stage("effect" + L, [&] { lr.raw = renderSsgi(lr.gbuffer, direct, lr.masks.stencil, f.view, lc, c.ssgi); });
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
    stage("blend", [&] { f.blend = composePeer(f.blendInputs(), gbuffers, f.tileRates, c, options.keepStages); });
  } else {
    stage("blend", [&] { f.blend = blendLevels(f.blendInputs(), c, options.keepStages); });
  }
  // 6. The shaded image for viewing (SPEC §6).
  stage("shade", [&] {
    f.shaded = shadeFinal(f.levels[0].gbuffer, f.blend.final, f.shadowLit, f.view, scene_.light, c.effect);
  });
  f.timings.push_back({"total", msSince(frameStart)});
  return f;
}

}  // namespace mrr
