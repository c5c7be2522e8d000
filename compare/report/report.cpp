#include "compare/report/report.h"

#include "common/frame_params.h"

#include <cmath>

#include "common/stage_images.h"
#include "common/stages.h"

namespace mrr {

std::vector<int64_t> shadedLevelPixelsByRing(const FrameResult& f, int rings, const std::function<int(int, int)>& ringOf) {
  const Constants& c = f.constants;
  std::vector<int64_t> shaded(static_cast<size_t>(rings), 0);
  for (int l = 0; l < kLevelCount; ++l) {
    if (!c.levels[static_cast<size_t>(l)].enabled) continue;
    const ImageU8& s = f.levels[static_cast<size_t>(l)].masks.stencil;
    const int scale = 1 << l;
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        const int px = levelSamplePixel(x, scale), py = levelSamplePixel(y, scale);
        if (!s.at(x, y) || px >= c.width || py >= c.height) continue;
        ++shaded[static_cast<size_t>(ringOf(px, py))];
      }
  }
  return shaded;
}

FrameErrors errorVsFull(const FrameResult& frame, const FrameResult& reference) {
  // FLIP's viewing conditions are --ppd's (SPEC §13); its default is FLIP's own, kept in double.
  const float ppdSet = frame.constants.foveation.ppd;
  const double ppd = ppdSet == FoveationSettings{}.ppd ? kFlipDefaultPpd : static_cast<double>(ppdSet);
  FrameErrors e{compareToReference(frame.final(), reference.final(), frame.blend.levelMap),
                compareToReference(frame.shaded, reference.shaded, frame.blend.levelMap),
                flip(reference.final(), frame.final(), ppd).stats,  // flip() clamps: the PNG preview's values
                flip(linearToDisplay(reference.shaded), linearToDisplay(frame.shaded), ppd).stats,
                {}};
  if (!frame.eccentricity.empty()) {  // SPEC §13: RMS per eccentricity ring, in double, in order
    std::vector<double> sum(kRingCount, 0.0);
    std::vector<int64_t> count(kRingCount, 0);
    const ImageF& a = frame.final();
    const ImageF& b = reference.final();
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        const int ring = eccentricityRing(frame.eccentricity.at(x, y));
        for (int ch = 0; ch < a.channels; ++ch) {
          const double d = static_cast<double>(a.at(x, y, ch)) - static_cast<double>(b.at(x, y, ch));
          sum[static_cast<size_t>(ring)] += d * d;
          ++count[static_cast<size_t>(ring)];
        }
      }
    for (int r = 0; r < kRingCount; ++r)
      e.ringRms.push_back(count[static_cast<size_t>(r)] ? std::sqrt(sum[static_cast<size_t>(r)] / static_cast<double>(count[static_cast<size_t>(r)])) : 0.0);
  }
  return e;
}

namespace {
nlohmann::json figuresJson(const ErrorFigures& e) {
  return {{"rms", e.rms},
          {"psnr", std::isfinite(e.psnr) ? nlohmann::json(e.psnr) : nlohmann::json(nullptr)},
          {"ssim", e.ssim},
          {"max_abs", e.maxAbs},
          {"edge_band_rms", e.edgeBandRms},
          {"edge_band_pixels", e.edgeBandPixels}};
}
}  // namespace

nlohmann::json makeReport(const FrameResult& f, const RunInfo& info, const std::optional<FrameErrors>& err) {
  const Constants& c = f.constants;
  nlohmann::json j;
  j["scene"] = info.scene;
  j["credit"] = info.credit;
  j["effect"] = toString(c.effect);
  j["path"] = info.path;
  j["mode"] = toString(c.mode);
  j["method"] = toString(c.mode);
  const std::string rule(paramInfo(Param::NeverSlower).key);  // the rule's object: its decision and counts
  if (f.fallback.evaluated)
    j[rule] = {{"fell_back_to_full", f.fallback.fellBack},
                         {"decided", f.fallback.onFloor ? "early, on the floor, before the edge sample"
                                     : f.fallback.early   ? "early, before the edges"
                                                          : "on the stencils"},
                         {"hit_pixels", f.counts.hitPixels},
                         {"silhouette_pixels", f.counts.silhouette[0]},
                         {"predicted_full_ms", f.fallback.predictedFullMs},
                         {"predicted_mrr_ms", f.fallback.predictedMrrMs},
                         {"predicted_gain_ms", f.fallback.predictedFullMs - f.fallback.predictedMrrMs},
                         {std::string(paramInfo(Param::CostModel).key), f.fallback.costModel}};
  if (f.fallback.evaluated && f.edgeSampled)  // 8×8 blocks whose diagonal holds an edge (or a silhouette)
    j[rule]["edge_sample_blocks"] = f.counts.edgeBlocks;
  if (f.fallback.evaluated && c.effect == Effect::Ssm) {  // H_a and H_p, from one pixel in 8×8
    j[rule]["searched_pixels"] = f.counts.searchedPixels;
    j[rule]["pcf_pixels"] = f.counts.pcfPixels;
    j[rule]["map_footprint_texels"] = footprintTexels(c.levels[0], f.counts);  // f̄
  }
  if (methodInfo(c.mode).masks == MaskBuilder::Tiles) {
    std::array<int, 3> tiles{};
    for (uint8_t r : f.tileRates.data) ++tiles[r];
    j[toString(c.mode)] = {{"size", kTileSize}, {"rate_1x1", tiles[0]}, {"rate_2x2", tiles[1]}, {"rate_4x4", tiles[2]}};
  }
  auto vec3 = [](const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  if (c.foveation.active()) {  // SPEC §13: the viewing conditions, the terms and what they allowed
    const Constants::Foveation& fv = c.foveation;
    nlohmann::json fj = {{"ppd", fv.ppd},
                         {"gaze", fv.gaze ? nlohmann::json::array({fv.gazeX, fv.gazeY}) : nlohmann::json(nullptr)},
                         {"foveate", fv.gaze && fv.foveate},
                         {"mar0_degrees", fv.mar0},
                         {"mar_slope", fv.marSlope},
                         {"motion", fv.motion}};
    if (fv.motion && fv.panned) {  // --pan: this frame's camera, its eye moved along its right axis
      const View prev = previousView(c, f.view);
      fj["pan"] = fv.pan;
      fj["prev_camera"] = {{"eye", vec3(prev.eye)}, {"target", vec3(f.camera.target - fv.pan * prev.right)},
                           {"up", vec3(f.camera.up)}, {"yfov_degrees", glm::degrees(f.camera.yfov)},
                           {"motion_cap", fv.motionCap}, {"motion_scale", fv.motionScale}};
    } else if (fv.motion) {
      fj["prev_camera"] = {{"eye", vec3(fv.prevEye)}, {"target", vec3(fv.prevTarget)}, {"up", vec3(fv.prevUp)},
                           {"yfov_degrees", glm::degrees(fv.prevYfov)}, {"motion_cap", fv.motionCap},
                           {"motion_scale", fv.motionScale}};
    }
    if (!f.levelLimit.empty()) {  // full-res pixels of W×H by ℓ_min
      std::array<int64_t, kLevelCount> byLimit{};
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) ++byLimit[f.levelLimit.at(x, y, 2)];
      fj["pixels_by_level_limit"] = byLimit;
    }
    if (!f.eccentricity.empty()) {  // per eccentricity ring: its pixels and the level pixels shaded there
      std::vector<int64_t> pixels(kRingCount, 0);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) ++pixels[static_cast<size_t>(eccentricityRing(f.eccentricity.at(x, y)))];
      const std::vector<int64_t> shaded = shadedLevelPixelsByRing(
          f, kRingCount, [&](int px, int py) { return eccentricityRing(f.eccentricity.at(px, py)); });
      nlohmann::json rings = nlohmann::json::array();
      for (int r = 0; r < kRingCount; ++r) {
        const size_t i = static_cast<size_t>(r);
        nlohmann::json ring = {{"from_degrees", r * kRingDegrees},
                               {"to_degrees", r + 1 < kRingCount ? nlohmann::json(r * kRingDegrees + kRingDegrees) : nlohmann::json(nullptr)},
                               {"pixels", pixels[i]},
                               {"shaded_level_pixels", shaded[i]},
                               {"shaded_share", pixels[i] ? static_cast<double>(shaded[i]) / static_cast<double>(pixels[i]) : 0.0}};
        if (err && i < err->ringRms.size())
          ring["rms_vs_full"] = pixels[i] ? nlohmann::json(err->ringRms[i]) : nlohmann::json(nullptr);
        rings.push_back(ring);
      }
      fj["rings"] = rings;
    }
    j["foveation"] = fj;
  }
  j["camera"] = {{"eye", vec3(f.camera.eye)},
                 {"target", vec3(f.camera.target)},
                 {"up", vec3(f.camera.up)},
                 {"yfov_degrees", glm::degrees(f.camera.yfov)}};
  j["light"] = {{"direction", vec3(f.light.direction)},  // the way the light travels
                {"toward_light", vec3(-f.light.direction)},  // what --light-dir takes
                {"color", vec3(f.light.color)},
                {"angular_diameter_rad", 2.0f * std::atan(c.ssm.tanHalfAngle)}};
  j["width"] = c.width;
  j["height"] = c.height;
  j["padded_width"] = c.paddedWidth;
  j["padded_height"] = c.paddedHeight;
  j["samples"] = c.samples();
  j["threads"] = info.threads;
  j["memory"] = {{"estimate_bytes", info.memoryEstimateBytes}, {"peak_resident_bytes", info.peakResidentBytes}};
  switch (c.effect) {
    case Effect::Ssao:
      j["ssao"] = {{"radius", c.ssao.radius}, {"bias", c.ssao.bias}, {"tangent_plane_depth", c.ssao.tangentPlaneDepth}};
      break;
    case Effect::Ssm:
      j["ssm"] = {{"pcf_grid", c.ssm.grid}, {std::string(paramInfo(Param::ShadowMapSize).key), c.ssm.shadowMapSize},
                  {"tan_half_light_angle", c.ssm.tanHalfAngle}, {"blocker_grid", c.ssm.blockerGrid},
                  {"bias_texels", c.ssm.biasTexels}};
      break;
    case Effect::Ssgi:
      j["ssgi"] = {{"radius", c.ssgi.radius}, {"patch_area", c.ssgi.patchArea}, {std::string(paramInfo(Param::ShadowMapSize).key), c.ssm.shadowMapSize}};
      break;
  }
  j["edges"] = {{std::string(paramInfo(Param::TauN).key), c.edges.normalThreshold},
                {std::string(paramInfo(Param::TauZ).key), c.edges.depthThreshold}};
  nlohmann::json levels = nlohmann::json::array();
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    levels.push_back({{"level", l}, {"scale", lc.scale}, {"enabled", lc.enabled}, {"shaded", lc.shaded}, {"width", lc.width},
                      {"height", lc.height}, {"sigma2", lc.sigma2}, {"weight", lc.weight},
                      {"shaded_pixels", f.levels[static_cast<size_t>(l)].shadedPixels},
                      {"shaded_pixels_4x2_blocks", f.levels[static_cast<size_t>(l)].shadedBlockPixels}});
  }
  j["levels"] = levels;
  // SPEC §12.4: per shaded level, the cost model's prediction on its final stencil beside the
  // measured time of its effect stages (so the model can be checked), and the budget's figures.
  if (methodInfo(c.mode).neverSlower && !f.fallback.early) {
    nlohmann::json budget = nlohmann::json::array();
    for (int l = 0; l < kLevelCount; ++l) {
      const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
      if (!lc.enabled || !lc.shaded) continue;
      double measured = 0.0;
      for (const StageTiming& t : f.timings)
        for (const Timed kind : {Timed::Planes, Timed::Direct, Timed::Effect, Timed::Bilateral})
          if (t.stage == timedName(kind, l)) measured += t.ms;
      const RefinementRecord& r = f.refinement[static_cast<size_t>(l)];
      nlohmann::json lj = {{"level", l}, {"predicted_ms", f.predictedLevelMs[static_cast<size_t>(l)]}, {"measured_ms", measured}};
      if (r.budgeted)
        lj.update({{"budget_ms", r.budgetNs() * 1e-6}, {"spent_ms", r.spentNs() * 1e-6}, {"candidates", r.candidates},
                   {"taken", r.taken}, {"kept", r.kept}});
      budget.push_back(lj);
    }
    j[std::string(paramInfo(Param::EffectBudget).key)] = {{"budget", c.effectMask.budget}, {"levels", budget}};
  }
  // SPEC §14: the temporal term, where it ran: its λ and the pixels that kept part of the history.
  if (!f.temporal.empty() && !f.temporal.weight.empty()) {
    int64_t kept = 0;
    double weight = 0.0;
    for (float w : f.temporal.weight.data) {
      kept += w > 0.0f;
      weight += w;
    }
    j["temporal"] = {{"lambda", c.temporal.lambda}, {"pixels_keeping_history", kept},
                     {"mean_lambda_p", f.temporal.weight.data.empty() ? 0.0 : weight / static_cast<double>(f.temporal.weight.data.size())}};
  }
  j["shaded_pixels_total"] = f.shadedPixelsTotal;
  j["ideal_speedup"] = f.idealSpeedup;
  j["ideal_speedup_hit"] = f.idealSpeedupHit;  // over pixels that hit geometry: background is free in full too
  j["ideal_speedup_4x2_blocks"] = f.blockIdealSpeedup;  // llvmpipe shades whole 4×2 blocks
  nlohmann::json timings = nlohmann::json::object();
  for (const StageTiming& t : f.timings)  // a stage timed twice (the rule's) is their sum
    timings[t.stage] = timings.value(t.stage, 0.0) + t.ms;
  j["timings_ms"] = timings;
  if (info.path == "gpu") {
    j["renderer"] = info.renderer;
    j["timing_method"] = info.timingMethod;
    // What the frame said to the host (gpu/traffic.h; docs/port.md, "What a frame costs the host"):
    // inside the timed frame, the clock's own waits apart; then after it, and the whole process.
    const auto traffic = [](const GlTraffic& t) {
      return nlohmann::json{{"readbacks", t.readbacks}, {"readback_bytes", t.readbackBytes}, {"count_reads", t.countReads},
                            {"waits", t.waits}, {"timing_waits", t.timingWaits}, {"finishes", t.finishes}};
    };
    if (!f.passTimings.empty()) {  // --gpu-timing passes: each program's draws, per stage
      nlohmann::json passes = nlohmann::json::array();
      for (const PassTiming& p : f.passTimings)
        passes.push_back({{"stage", p.stage}, {"pass", p.pass}, {"shader", p.shader}, {"calls", p.calls}, {"ms", p.ms}});
      j["passes"] = passes;
    }
    if (f.gl.measured) {
      j["gl"] = traffic(f.gl);
      j["gl"]["after_frame"] = traffic(f.glAfterFrame);
      j["gl"]["process"] = traffic(f.glProcess);
    }
  } else {
    j["timing_method"] = "wall clock (steady_clock) around each stage";
  }
  if (err) {
    j["error_vs_full"] = figuresJson(err->effect);  // psnr null = identical images
    j["error_vs_full"]["flip"] = nlohmann::json(err->effectFlip);
    j["error_vs_full_shaded"] = figuresJson(err->shaded);
    j["error_vs_full_shaded"]["flip"] = nlohmann::json(err->shadedFlip);
  }
  return j;
}

// Every part the frame holds, each read by its row's accessor (common/stage_images.h).
std::vector<ExrPart> stageParts(const FrameResult& f) {
  std::vector<ExrPart> parts;
  for (const PartRef& ref : heldParts(f)) {
    ImageF image = readPart(f, ref.part, ref.level);
    std::vector<std::string> channels = partChannels(ref.part, image);
    parts.push_back({ref.name(), std::move(image), std::move(channels)});
  }
  return parts;
}

void writeFinal(const std::string& path, const FrameResult& frame) { writeImage(path, frame.final(), {}, false); }

void writeShaded(const std::string& path, const FrameResult& frame) { writeImage(path, frame.shaded, {}, true); }

}  // namespace mrr
