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

#include <chrono>
#include <cstdio>
#include <functional>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

#include "common/effect_budget.h"
#include "common/error.h"
#include "common/params.h"
#include "common/paths.h"
#include "common/stages.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/masks.h"
#include "cpu_ref/oracle.h"
#include "cpu_ref/pipeline.h"
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
  std::unique_ptr<Renderer> renderer;
  FrameResult f;
  FrameResult dense;  // f with level 0's stencil all set: the dense reference
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
    s.mode = parseMode(envOr("MRR_BENCH_METHOD", toString(Mode::Mrr)));
    SceneRequest request;
    request.scene = sceneName;
    request.aspect = static_cast<float>(s.width) / static_cast<float>(s.height);
    ResolvedScene resolved = resolveScene(request);
    fr->scene = std::make_unique<Scene>(std::move(resolved.scene));
    fr->renderer = std::make_unique<Renderer>(*fr->scene);
    fr->f = fr->renderer->render(resolved.camera, makeConstants(s, resolved.framed.size));
    const LevelConstants& l0 = fr->f.constants.levels[0];
    fr->dense = fr->f;
    fr->dense.levels[0].masks.stencil = ImageU8(l0.width, l0.height, 1, 1);
    fr->label = sceneName + " " + size + " " + toString(s.effect) + " " + toString(s.mode);
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

// Registers one benchmark that times only the effect itself (the `effect.Lℓ` stage of
// OracleStages::raw), not its per-level sub-steps (SSAO's occluder planes, SSGI's direct light).
void addEffect(const std::string& name, int64_t pixels, const FrameResult& in, int level) {
  benchmark::RegisterBenchmark(name.c_str(),
                               [&in, level, pixels](benchmark::State& state) {
                                 state.SetLabel(frame().label);
                                 const OracleStages& oracle = frame().renderer->stages();
                                 const std::string effect = timedName(Timed::Effect, level);
                                 for (auto _ : state) {
                                   double seconds = 0.0;
                                   benchmark::DoNotOptimize(oracle.raw(in, level, [&](const std::string& stage, const std::function<void()>& body) {
                                     const auto t0 = std::chrono::steady_clock::now();
                                     body();
                                     if (stage == effect) seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                                   }));
                                   state.SetIterationTime(seconds);
                                 }
                                 state.SetItemsProcessed(state.iterations() * pixels);
                               })
      ->Unit(benchmark::kMillisecond)
      ->UseManualTime();
}

// The stages of the prepared frame that it renders: its enabled levels, its effect, each as the
// oracle's stage object runs it (cpu_ref/oracle.h).
void registerStages() {
  Frame& fr = frame();
  const OracleStages& oracle = fr.renderer->stages();
  const Constants& c = fr.f.constants;
  const FrameResult& f = fr.f;
  const LevelResult& l0 = f.levels[0];
  const int64_t full = static_cast<int64_t>(c.levels[0].width) * c.levels[0].height;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    if (l == 0)  // rays; the coarser levels are level 0 subsampled (SPEC §1)
      add(timedName(Timed::GBuffer, l), static_cast<int64_t>(lc.width) * lc.height,
          [&oracle, &f, &lc] { benchmark::DoNotOptimize(oracle.gbuffer(f.view, lc)); });
    else
      add(timedName(Timed::GBuffer, l), static_cast<int64_t>(lc.width) * lc.height,
          [&oracle, &f, l] { benchmark::DoNotOptimize(oracle.coarseGBuffer(f, l)); });
  }
  add(stageName(Part::Edges), full, [&oracle, &f] { benchmark::DoNotOptimize(oracle.edges(f)); });
  // The method's masks, as its row's mask builder makes them (no level limit).
  const std::string masks = timedName(Timed::Masking);
  add(masks, full, [&oracle, &f] { benchmark::DoNotOptimize(oracle.masks(f)); });
  if (methodInfo(c.mode).masks == MaskBuilder::EffectEdges) {  // SPEC §12: the footprint, then the widened M_ℓ
    auto footprint = std::make_shared<ImageF>(oracle.footprint(f));
    add(masks + "/footprint", full, [&oracle, &f] { benchmark::DoNotOptimize(oracle.footprint(f)); });
    add(masks + "/widen", full, [&oracle, &f, footprint] { benchmark::DoNotOptimize(oracle.maskStages(f, footprint.get())); });
    add(masks + "/widened_rest", full, [&oracle, &f, footprint] { benchmark::DoNotOptimize(oracle.effectMasks(f, footprint.get())); });
    if (c.effectMask.trim) {  // SPEC §12.5 alone, on the frame's untrimmed a-priori masks
      FrameResult untrimmed = f;
      untrimmed.constants.effectMask.trim = false;
      auto whole = std::make_shared<Masks>(oracle.effectMasks(untrimmed, footprint.get()));
      add(masks + "/trim", full, [&c, whole] {
        Masks m = *whole;
        trimToBlend(m, c);
        benchmark::DoNotOptimize(m);
      });
    }
  }
  // SPEC §12.2's a-posteriori term, per refined level (the frame's `masks` stage holds these too):
  // the marks from the next coarser level's result (the 3×3 range, with a budget the candidates'
  // prices and the selection), then M_ℓ ∨= marks and the re-blur, on the frame's a-priori masks.
  for (int l = 0; l < kLevelCount; ++l) {
    if (f.levels[static_cast<size_t>(l)].marks.empty()) continue;
    const std::string level = ".L" + std::to_string(l);
    add(masks + "/marks" + level, full, [&oracle, &f, l] { benchmark::DoNotOptimize(oracle.marks(f, l)); });
    add(masks + "/range" + level, full, [&f, l] {
      const LevelResult& coarser = f.levels[static_cast<size_t>(f.constants.nextCoarserEnabled(l))];
      benchmark::DoNotOptimize(localRangesSeparable(coarser.sub, coarser.masks.stencil, coarser.gbuffer.hit));
    });
    const RefinementRecord& r = f.refinement[static_cast<size_t>(l)];
    if (r.budgeted)
      add(masks + "/prices" + level, full, [&f, &r, l] {
        benchmark::DoNotOptimize(candidatePrices(f.levels[static_cast<size_t>(l)].masks.stencil, f.levels[0].gbuffer.hit,
                                                 f.pcfSample, f.constants, l, f.constants.nextCoarserEnabled(l), r.units));
      });
    add(masks + "/refine" + level, full, [&oracle, &f, l] {
      MaskLevel level = f.levels[static_cast<size_t>(l)].masks;  // a copy: the refinement changes it
      oracle.refine(level, f.levels[static_cast<size_t>(l)].marks, f.constants.levels[static_cast<size_t>(l)]);
      benchmark::DoNotOptimize(level);
    });
  }
  // The never-slower rule's own work before its early decision (SPEC §11, its stage `rule`):
  // the edge sample, and the counts of H, B_ℓ and the sample's reach.
  const std::string rule = timedName(Timed::Rule);
  add(rule + "/edge_sample", full, [&oracle, &f] { benchmark::DoNotOptimize(oracle.edgeSample(f)); });
  add(rule + "/count_hits", full, [&l0, &c] {
    FrameCounts n;
    countHits(n, l0.gbuffer.hit, ImageU8(), c);
    benchmark::DoNotOptimize(n);
  });
  {
    auto sample = std::make_shared<ImageU8>(oracle.edgeSample(f));
    auto silhouettes = std::make_shared<ImageU8>();
    FrameCounts counted;
    countHits(counted, l0.gbuffer.hit, ImageU8(), c, silhouettes.get());
    add(rule + "/count_edge_sample", full, [&l0, &c, sample, silhouettes] {
      FrameCounts n;
      countEdgeSample(n, *sample, *silhouettes, l0.gbuffer.hit, c);
      benchmark::DoNotOptimize(n);
    });
  }
  // ... and its second part, on the stencils: |S_ℓ| and how many of them lie on geometry.
  {
    auto stencils = std::make_shared<Masks>();
    for (size_t l = 0; l < stencils->size(); ++l) (*stencils)[l] = f.levels[l].masks;
    add(rule + "/count_stencils", full, [&l0, &c, stencils] {
      FrameCounts n;
      countForRule(n, *stencils, c, l0.gbuffer.hit, ImageU8());
      benchmark::DoNotOptimize(n);
    });
  }
  // The effect (and SSAO's bilateral blur) at each level over its own S_ℓ, and at level 0 over
  // every pixel too ("dense"): pixels per second, side by side.
  const auto effect = [&](const std::string& suffix, const FrameResult& in, int l, int64_t pixels) {
    addEffect("effect/" + suffix, pixels, in, l);
    if (c.effect == Effect::Ssao)
      add("bilateral/" + suffix, pixels, [&oracle, &in, l] {
        benchmark::DoNotOptimize(oracle.sub(in, l, in.levels[static_cast<size_t>(l)].raw));
      });
  };
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled || !lc.shaded) continue;
    const std::string level = "L" + std::to_string(l);
    effect(level, f, l, f.levels[static_cast<size_t>(l)].shadedPixels);
    if (l == 0) effect(level + "/dense", fr.dense, l, full);
  }
  // The blend: the final image alone (what `mrr bench` times), and with every stage image kept.
  const std::string blend = timedName(Timed::Blend);
  add(blend, full, [&oracle, &f] { benchmark::DoNotOptimize(oracle.blend(f, false)); });
  add(blend + "/keep_stages", full, [&oracle, &f] { benchmark::DoNotOptimize(oracle.blend(f, true)); });
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
