// mrr_stage_bench: Google Benchmark micro-benchmarks of the oracle's stages, each timed alone
// on the inputs of one prepared frame. It is the tool for tuning a stage: the figures the docs
// quote come from `mrr bench`, which times whole frames, full and the method side by side.
//
//   build/mrr_stage_bench [--benchmark_filter=REGEX] [--benchmark_repetitions=N]
//
// The frame: MRR_BENCH_SCENE (default arcade, or builtin:demo where ../shared/scenes is not
// there), MRR_BENCH_SIZE (default 1280x720), MRR_BENCH_EFFECT (ssao, ssm or ssgi; default ssao),
// camera 0, the paper's defaults, the never-slower rule off. Every benchmark reports its shaded
// (or visited) pixels per second, so a stage on the sparse stencil of level ℓ compares with the
// same stage on every pixel ("dense"): how much more an edge pixel costs than an average one.
#include <benchmark/benchmark.h>
#include <malloc.h>
#include <sys/prctl.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "common/error.h"
#include "common/params.h"
#include "common/paths.h"
#include "common/stages.h"
#include "cpu_ref/bilateral.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/peers.h"
#include "cpu_ref/pipeline.h"
#include "cpu_ref/ssgi.h"
#include "cpu_ref/ssm.h"
#include "scenes/catalog.h"

namespace mrr {
namespace {

std::string envOr(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

// One frame, rendered once with every stage kept: the inputs of the benchmarks below.
struct Frame {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<RayScene> rays;
  std::unique_ptr<Renderer> renderer;
  FrameResult f;
  ImageU8 everyPixel;  // level 0 all set: the dense reference
  std::string label;
};

Frame& frame() {
  static Frame* frame = [] {
    auto* fr = new Frame;
    const std::string sceneName =
        envOr("MRR_BENCH_SCENE", std::filesystem::exists(sharedScenesDir()) ? "arcade" : "builtin:demo");
    const std::string size = envOr("MRR_BENCH_SIZE", "1280x720");
    Settings s = defaultSettings(parseEffect(envOr("MRR_BENCH_EFFECT", "ssao")));
    if (std::sscanf(size.c_str(), "%dx%d", &s.width, &s.height) != 2)
      throw MrrError("MRR_BENCH_SIZE=" + size + ": expected WIDTHxHEIGHT");
    s.neverSlower = false;
    s.mode = parseMode(envOr("MRR_BENCH_METHOD", "mrr"));
    SceneRequest request;
    request.scene = sceneName;
    request.aspect = static_cast<float>(s.width) / static_cast<float>(s.height);
    ResolvedScene resolved = resolveScene(request);
    fr->scene = std::make_unique<Scene>(std::move(resolved.scene));
    fr->rays = std::make_unique<RayScene>(*fr->scene);
    fr->renderer = std::make_unique<Renderer>(*fr->scene);
    fr->f = fr->renderer->render(resolved.camera, makeConstants(s, resolved.framed.size));
    const LevelConstants& l0 = fr->f.constants.levels[0];
    fr->everyPixel = ImageU8(l0.width, l0.height, 1, 1);
    fr->label = sceneName + " " + size + " " + toString(s.effect) + " " + envOr("MRR_BENCH_METHOD", "mrr");
    std::fprintf(stderr, "mrr_stage_bench: %s, |S_l| = %lld %lld %lld %lld\n", fr->label.c_str(),
                 static_cast<long long>(fr->f.levels[0].shadedPixels), static_cast<long long>(fr->f.levels[1].shadedPixels),
                 static_cast<long long>(fr->f.levels[2].shadedPixels), static_cast<long long>(fr->f.levels[3].shadedPixels));
    return fr;
  }();
  return *frame;
}

// Registers one benchmark: `body` runs the stage once; `pixels` it shades or visits.
template <class Body>
void add(const std::string& name, int64_t pixels, Body body) {
  benchmark::RegisterBenchmark(name.c_str(),
                               [=](benchmark::State& state) {
                                 state.SetLabel(frame().label);
                                 for (auto _ : state) body();
                                 state.SetItemsProcessed(state.iterations() * pixels);
                               })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
}

// The stages of the prepared frame that it renders: its enabled levels, its effect.
void registerStages() {
  Frame& fr = frame();
  const Constants& c = fr.f.constants;
  const FrameResult& f = fr.f;
  const LevelResult& l0 = f.levels[0];
  const int64_t full = static_cast<int64_t>(c.levels[0].width) * c.levels[0].height;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const char* names[kLevelCount] = {"gbuffer/L0", "gbuffer/L1", "gbuffer/L2", "gbuffer/L3"};
    if (l == 0)  // rays; the coarser levels are level 0 subsampled (SPEC §1)
      add(names[l], static_cast<int64_t>(lc.width) * lc.height,
          [&fr, &lc] { benchmark::DoNotOptimize(renderGBuffer(*fr.rays, fr.f.view, lc)); });
    else
      add(names[l], static_cast<int64_t>(lc.width) * lc.height,
          [&l0, &lc] { benchmark::DoNotOptimize(subsampleGBuffer(l0.gbuffer, lc)); });
  }
  const ImageU8* shadowEdges = c.effect == Effect::Ssm ? &f.shadowLit : nullptr;
  add(stageName(Part::Edges), full, [&l0, &c, shadowEdges] { benchmark::DoNotOptimize(detectEdges(l0.gbuffer, c.edges, shadowEdges)); });
  // The method's masks, as OracleFrame::methodMasks and tileMasks make them (no level limit).
  const ShadowMap* map = c.needsShadowMap() ? &f.shadowMap : nullptr;
  switch (c.mode) {
    case Mode::MrrEffect: {  // SPEC §12: the footprint, then the paper's masks from the widened M_ℓ
      auto footprint = std::make_shared<ImageF>(effectFootprint(l0.gbuffer, f.edges.combined, f.view, map, c));
      add("masks", full, [&f, &l0, &c, map] {
        const ImageF fp = effectFootprint(l0.gbuffer, f.edges.combined, f.view, map, c);
        benchmark::DoNotOptimize(buildMasks(f.edges.combined, c, &fp));
      });
      add("masks/footprint", full, [&f, &l0, &c, map] {
        benchmark::DoNotOptimize(effectFootprint(l0.gbuffer, f.edges.combined, f.view, map, c));
      });
      add("masks/widen", full, [&f, &c, footprint] { benchmark::DoNotOptimize(maskStages(f.edges.combined, c, footprint.get())); });
      add("masks/widened_rest", full, [&f, &c, footprint] { benchmark::DoNotOptimize(buildMasks(f.edges.combined, c, footprint.get())); });
      break;
    }
    case Mode::Tiles:
      add("masks", full, [&f, &c] { benchmark::DoNotOptimize(tileMasks(tileRates(f.edges.combined), c)); });
      break;
    default: add("masks", full, [&f, &c] { benchmark::DoNotOptimize(buildMasks(f.edges.combined, c)); });
  }
  // The never-slower rule's own work before its early decision (SPEC §11, its stage `rule`):
  // the edge sample, and the counts of H, B_ℓ and the sample's reach.
  add("rule/edge_sample", full, [&l0, &c, shadowEdges] { benchmark::DoNotOptimize(edgeSample(l0.gbuffer, c.edges, shadowEdges)); });
  add("rule/count_hits", full, [&l0, &c] {
    FrameCounts n;
    countHits(n, l0.gbuffer.hit, ImageU8(), c);
    benchmark::DoNotOptimize(n);
  });
  {
    auto sample = std::make_shared<ImageU8>(edgeSample(l0.gbuffer, c.edges, shadowEdges));
    auto silhouettes = std::make_shared<ImageU8>();
    FrameCounts counted;
    countHits(counted, l0.gbuffer.hit, ImageU8(), c, silhouettes.get());
    add("rule/count_edge_sample", full, [&l0, &c, sample, silhouettes] {
      FrameCounts n;
      countEdgeSample(n, *sample, *silhouettes, l0.gbuffer.hit, c);
      benchmark::DoNotOptimize(n);
    });
  }
  // ... and its second part, on the stencils: |S_ℓ| and how many of them lie on geometry.
  {
    auto masks = std::make_shared<Masks>();
    for (size_t l = 0; l < masks->size(); ++l) (*masks)[l] = f.levels[l].masks;
    add("rule/count_stencils", full, [&l0, &c, masks] {
      FrameCounts n;
      countForRule(n, *masks, c, l0.gbuffer.hit, ImageU8());
      benchmark::DoNotOptimize(n);
    });
  }
  // The effect (and SSAO's bilateral blur) at each level over its own S_ℓ, and at level 0 over
  // every pixel too ("dense"): pixels per second, side by side.
  // `pixels`: |S_ℓ| as the frame counted it, or every pixel for the dense run.
  auto effect = [&fr, &f, &c](const std::string& name, const LevelResult& lr, const LevelConstants& lc,
                              const ImageU8& stencil, int64_t pixels) {
    switch (c.effect) {
      case Effect::Ssao: {
        auto planes = std::make_shared<OccluderPlanes>(occluderPlanes(lr.gbuffer));
        add("effect/" + name, pixels, [&fr, &lr, &lc, &c, &stencil, planes] {
          benchmark::DoNotOptimize(renderSsao(lr.gbuffer, *planes, stencil, fr.f.view, lc, c.ssao));
        });
        add("bilateral/" + name, pixels, [&lr, &c, &stencil] {
          benchmark::DoNotOptimize(bilateralBlur(lr.raw, stencil, lr.gbuffer, c.bilateral));
        });
        break;
      }
      case Effect::Ssm:
        add("effect/" + name, pixels, [&f, &lr, &c, &stencil] {
          benchmark::DoNotOptimize(renderSsm(lr.gbuffer, f.shadowMap, stencil, f.view, c.ssm));
        });
        break;
      case Effect::Ssgi: {
        auto direct = std::make_shared<ImageF>(directLight(lr.gbuffer, f.shadowMap, f.view, f.light, c.ssm.biasTexels));
        add("effect/" + name, pixels, [&f, &lr, &lc, &c, &stencil, direct] {
          benchmark::DoNotOptimize(renderSsgi(lr.gbuffer, *direct, stencil, f.view, lc, c.ssgi));
        });
        break;
      }
    }
  };
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const LevelResult& lr = f.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const char* names[kLevelCount] = {"L0", "L1", "L2", "L3"};
    effect(names[l], lr, lc, lr.masks.stencil, lr.shadedPixels);
    if (l == 0) effect("L0/dense", lr, lc, fr.everyPixel, full);
  }
  // The blend: the final image alone (what `mrr bench` times), and with every stage image kept.
  add("blend", full, [&f, &c] { benchmark::DoNotOptimize(blendLevels(f.blendInputs(), c, false)); });
  add("blend/keep_stages", full, [&f, &c] { benchmark::DoNotOptimize(blendLevels(f.blendInputs(), c, true)); });
}

}  // namespace
}  // namespace mrr

int main(int argc, char** argv) {
  // A stage run alone frees its images at the top of glibc's heap, which then gives them back
  // to the kernel and faults them in again on the next run (masks measured 20 ms instead of the
  // pipeline's 6). In a frame other images sit above them; here glibc keeps them instead.
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  prctl(PR_SET_THP_DISABLE, 1, 0, 0, 0);  // as `mrr` (app/main.cpp): no huge pages' random clearing cost
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    mrr::registerStages();  // renders the frame first: bad settings fail here, before any timing
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mrr_stage_bench: %s\n", e.what());
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
