// `mrr render` (one frame: the effect buffer, the shaded image, the stages, the report) and
// `mrr probe` (one full-res pixel through every stage, on one path or both side by side).
#include <tbb/global_control.h>

#include <iostream>
#include <memory>

#include "app/byo.h"
#include "app/commands.h"
#include "common/error.h"
#include "common/image_io.h"
#include "common/memory.h"
#include "common/pixel_memory.h"
#include "common/stages.h"
#include "compare/parity/against.h"
#include "compare/parity/noise.h"
#include "compare/parity/probe_both.h"
#include "compare/report/report.h"
#include "cpu_ref/probe.h"
#include "frontend/options.h"
#include "frontend/renderers.h"

namespace mrr {

void addRenderCommand(CLI::App& app, RenderCommand& c) {
  c.command = app.add_subcommand("render", "render one frame and write the effect buffer, stages and report");
  c.frame.add(*c.command);
  c.command->add_option("--out", c.out, "final effect buffer: .exr (float) or .png (preview)");
  c.command->add_option("--shaded", c.shaded, "shaded image for viewing: .exr (linear) or .png (sRGB)");
  c.command->add_option("--stages", c.stages, "every stage as a multi-part .exr");
  c.command->add_option("--report", c.report, "JSON report: levels, shaded pixels, ideal speedup, timings");
  c.command->add_option("--frame-out", c.frameOut,
                        "the frame as a frame file (JSON): --frame reads it back and renders the same bits");
  c.command->add_flag("--reference", c.reference, "also render mode full and add error_vs_full to the report");
}

void addProbeCommand(CLI::App& app, ProbeCommand& c) {
  c.command = app.add_subcommand("probe", "follow one full-res pixel through every stage");
  c.frame.add(*c.command);
  c.command->add_option("--pixel", c.pixel, "X,Y of the full-res pixel")->required();
  c.command->add_flag("--json", c.json, "print JSON instead of text");
  addAgainstOption(*c.command, c.against);
  c.command->add_flag("--noise-aware", c.noiseAware,
                      "with --path both, ssao/ssgi: also each stochastic stage's mean over the oracle's independent "
                      "seeds, the interval compare --noise-aware accepts one draw in, and where the value falls in it");
}

namespace {

Settings checkedSettings(const FrameOptions& fo) {
  const Settings settings = fo.settings();
  require(fo.threads >= 0 && fo.threads <= 1024, optionName(Param::Threads) + ": must be in " + paramRange(Param::Threads));
  return settings;
}

ResolvedScene loadScene(const FrameOptions& fo) {
  if (!fo.quiet) std::cerr << "[mrr] loading " << fo.scene << "\n";
  ResolvedScene rs = resolveScene(fo.sceneRequest());
  if (!fo.quiet) std::cerr << "[mrr] " << rs.scene.triangleCount() << " triangles; building BVH\n";
  return rs;
}

Settings fullResolution(Settings s) {
  s.mode = Mode::Full;
  return s;
}

// The oracle and the port (or --against's file) on one frame, one pixel side by side.
int probeBothPaths(const ProbeCommand& c, const ResolvedScene& rs, const Constants& constants, int x, int y) {
  const FrameOptions& fo = c.frame;
  const std::unique_ptr<FrameRenderer> oracle = makeRenderer("cpu", rs.scene);
  std::unique_ptr<FrameRenderer> port;  // none with --against: the file's stages instead
  if (c.against.empty()) port = makeRenderer("gpu", rs.scene, fo.pathOptions());
  const CostModel costs = fo.costModel("cpu");
  // SPEC §14: each path's own previous frame first, where the temporal term reads one
  const Settings settings0 = fo.settings();
  const FrameHistory oracleBefore = previousFrameHistory(*oracle, rs.camera, settings0, rs.framed.size, &costs);
  const FrameHistory portBefore =
      port ? previousFrameHistory(*port, rs.camera, settings0, rs.framed.size, &costs) : FrameHistory{};
  RenderOptions oracleOptions{true, progressPrinter(fo.quiet, "oracle"), &costs}, portOptions{true, progressPrinter(fo.quiet, "port"), &costs};
  if (!oracleBefore.empty()) oracleOptions.history = &oracleBefore;
  if (!portBefore.empty()) portOptions.history = &portBefore;
  const FrameResult o = oracle->render(rs.camera, constants, oracleOptions);
  const FrameResult p = port ? port->render(rs.camera, constants, portOptions) : readForeignStages(c.against, o).frame;
  const nlohmann::json jo = probePixel(o, x, y), jp = probePixel(p, x, y);
  nlohmann::json both = probeBothJson(jo, jp);
  std::string text = c.json ? "" : formatProbeSideBySide(jo, jp, port ? port->device() : c.against);
  if (c.noiseAware && isStochastic(constants.effect)) {
    Settings settings = fo.settings();
    const NoiseReference noise = buildNoiseReference(
        [&](uint32_t seed) {
          settings.seed = seed;
          return oracle->render(rs.camera, makeConstants(settings, rs.framed.size), {true, {}, &costs});
        },
        constants.samples(), [&](int i, int n) {
          if (!fo.quiet) std::cerr << "[mrr] noise-aware: oracle seed " << i + 1 << "/" << n << "\n";
        });
    const NoisePixel pixel = noisePixel(o, p, noise, x, y);
    both["noise_aware"] = noisePixelJson(pixel);
    text += "\n" + formatNoisePixel(pixel, port ? "the port's" : "the file's");
  } else if (c.noiseAware && !fo.quiet) {
    std::cerr << "[mrr] noise-aware: " << toString(constants.effect) << " has no stochastic stage; every value exact\n";
  }
  std::cout << (c.json ? both.dump(2) + "\n" : text);
  return 0;
}

void checkRenderOutputs(const RenderCommand& c) {
  require(!c.out.empty() || !c.shaded.empty() || !c.stages.empty() || !c.report.empty() || !c.frameOut.empty(),
          "render: nothing to write (give --out, --shaded, --stages or --report)");
  if (!c.out.empty()) checkOutput(c.out, "--out", {".exr", ".png"});
  if (!c.shaded.empty()) checkOutput(c.shaded, "--shaded", {".exr", ".png"});
  if (!c.stages.empty()) checkOutput(c.stages, "--stages", {".exr"});
  if (!c.frameOut.empty()) checkOutput(c.frameOut, "--frame-out", {".json"});
  if (!c.report.empty()) checkOutput(c.report, "--report", {".json"});
  requireDistinct({{"--out", c.out}, {"--shaded", c.shaded}, {"--stages", c.stages}, {"--report", c.report},
                   {"--frame-out", c.frameOut}});
}

void printRenderSummary(const FrameResult& frame, const Constants& constants, const std::optional<FrameErrors>& err) {
  std::cerr << "[mrr] shaded " << frame.shadedPixelsTotal << " of " << constants.width * constants.height
            << " pixels: ideal speedup " << frame.idealSpeedup << "x (on geometry " << frame.idealSpeedupHit
            << "x: the background is free in full too); total " << frame.timing(timedName(Timed::Total)) << " ms, one run\n";
  if (frame.fallback.fellBack)
    std::cerr << "[mrr] never slower: predicted " << frame.fallback.predictedMrrMs << " ms mrr"
              << (frame.fallback.onFloor ? " at the least, before the edge sample,"
                  : frame.fallback.early ? " going on, before the edges,"
                                         : "")
              << " against " << frame.fallback.predictedFullMs << " ms full; shaded at full resolution\n";
  if (err)
    std::cerr << "[mrr] vs full: RMS " << err->effect.rms << ", SSIM " << err->effect.ssim << " (shaded: RMS "
              << err->shaded.rms << ")\n";
}

}  // namespace

int runProbeCommand(ProbeCommand& c) {
  FrameOptions& fo = c.frame;
  fo.checkPath(true);
  if (!c.against.empty()) {
    require(fo.path == "both", "--against " + c.against + ": probe compares the file's stages with the oracle: add --path both");
    checkForeignStagesFile(c.against, fo.effect);
    fo.neverSlowerDefault = false;  // as compare: the stages of every level, as `render --never-slower off` writes them
  }
  require(!c.noiseAware || fo.path == "both",
          "--noise-aware: probe judges a pixel's stochastic stages against the oracle's seeds: add --path both");
  const Settings settings = checkedSettings(fo);
  const auto [x, y] = parsePixel(c.pixel);
  require(x >= 0 && y >= 0 && x < settings.width && y < settings.height,
          "--pixel " + c.pixel + ": outside the " + fo.size + " image");
  const int64_t memoryEstimate = estimateFrameBytes(makeConstants(settings, 1.0f), true);
  requireMemory(memoryEstimate, memoryLimit(fo.memoryLimitGiB), "a " + fo.size + " " + toString(settings.effect) + " frame");
  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threadCount(fo.threads)));
  const ResolvedScene rs = loadScene(fo);
  const Constants constants = makeConstants(settings, rs.framed.size);
  if (fo.path == "both") return probeBothPaths(c, rs, constants, x, y);
  const std::unique_ptr<FrameRenderer> renderer = makeRenderer(fo.path, rs.scene, fo.pathOptions());
  if (!fo.quiet && fo.path == "gpu") std::cerr << "[mrr] GL renderer: " << renderer->device() << "\n";
  const CostModel costs = fo.costModel(fo.path);
  const FrameHistory previous = previousFrameHistory(*renderer, rs.camera, settings, rs.framed.size, &costs);  // SPEC §14
  RenderOptions options{true, progressPrinter(fo.quiet, toString(settings.mode)), &costs};
  if (!previous.empty()) options.history = &previous;
  const FrameResult frame = renderer->render(rs.camera, constants, options);
  const nlohmann::json j = probePixel(frame, x, y);
  std::cout << (c.json ? j.dump(2) + "\n" : formatProbe(j));
  return 0;
}

int runRenderCommand(RenderCommand& c) {
  FrameOptions& fo = c.frame;
  fo.checkPath();
  const Settings settings = checkedSettings(fo);
  checkRenderOutputs(c);
  // The memory check up front, before the scene is loaded or anything allocated: sizes alone
  // decide it (what the view frames only scales radii).
  const bool keepStages = !c.stages.empty();
  int64_t memoryEstimate = estimateFrameBytes(makeConstants(settings, 1.0f), keepStages);
  if (c.reference) memoryEstimate += estimateFrameBytes(makeConstants(fullResolution(settings), 1.0f), false);
  requireMemory(memoryEstimate, memoryLimit(fo.memoryLimitGiB),
                "a " + fo.size + " " + toString(settings.effect) + " frame" + (c.reference ? " and its reference" : ""));

  tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threadCount(fo.threads)));
  // The frame's pages are faulted in on a spare core while the scene loads (common/pixel_memory.h).
  PixelReservation pages(static_cast<size_t>(memoryEstimate));
  const ResolvedScene rs = loadScene(fo);
  const Constants constants = makeConstants(settings, rs.framed.size);
  const std::unique_ptr<FrameRenderer> renderer = makeRenderer(fo.path, rs.scene, fo.pathOptions());
  if (!fo.quiet && fo.path == "gpu") std::cerr << "[mrr] GL renderer: " << renderer->device() << "\n";
  // The per-level blend images are debugging output: kept only when something shows them.
  const CostModel costs = fo.costModel(fo.path);
  pages.wait();
  // SPEC §14: the previous frame first, where the temporal term reads one
  const FrameHistory previous =
      previousFrameHistory(*renderer, rs.camera, settings, rs.framed.size, &costs, progressPrinter(fo.quiet, "previous frame"));
  RenderOptions options{keepStages, progressPrinter(fo.quiet, toString(settings.mode)), &costs};
  if (!previous.empty()) options.history = &previous;
  // What comes back from the port after the frame: the images written, and the maps the report
  // reads (SPEC §13's, the tiles' rates); a report alone needs none (docs/port.md).
  const bool reportReadsMaps = !c.report.empty() && (constants.foveation.active() || settings.mode == Mode::Tiles);
  const bool reportReadsRings = !c.report.empty() && constants.foveation.gaze;  // shaded level pixels per ring
  options.outputs = c.reference ? kOutputAll
                                : (!c.out.empty() ? kOutputFinal : 0u) | (!c.shaded.empty() ? kOutputShaded : 0u) |
                                      (reportReadsMaps ? kOutputMaps : 0u) | (reportReadsRings ? kOutputStencils : 0u);
  const FrameResult frame = renderer->render(rs.camera, constants, options);

  std::optional<FrameErrors> err;
  if (c.reference) {
    const FrameResult ref = renderer->render(rs.camera, makeConstants(fullResolution(settings), rs.framed.size),
                                             {false, progressPrinter(fo.quiet, "reference")});
    err = errorVsFull(frame, ref);
  }
  RunInfo info{rs.scene.name, rs.scene.credit, fo.path, threadCount(fo.threads), {}, {}};
  if (fo.path == "gpu") {
    info.renderer = renderer->device();
    info.timingMethod = renderer->timingMethod();
  }
  info.memoryEstimateBytes = memoryEstimate;
  info.peakResidentBytes = peakResidentBytes();
  if (!c.out.empty()) writeFinal(c.out, frame);
  if (!c.shaded.empty()) writeShaded(c.shaded, frame);
  const nlohmann::json frameFile = fo.frame(rs, settings);
  if (!c.stages.empty())
    writeMultiPartExr(c.stages, stageParts(frame), constants.width, constants.height, {{"mrr:frame", frameFile.dump()}});
  if (!c.report.empty()) {
    nlohmann::json j = makeReport(frame, info, err);
    j["frame"] = frameFile;
    writeTextFile(c.report, j.dump(2) + "\n");
  }
  if (!c.frameOut.empty()) writeTextFile(c.frameOut, frameFile.dump(2) + "\n");
  if (!fo.quiet) printRenderSummary(frame, constants, err);
  return 0;
}

}  // namespace mrr
