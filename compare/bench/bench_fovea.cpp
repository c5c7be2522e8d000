#include "compare/bench/bench_fovea.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

#include "common/error.h"
#include "common/stages.h"
#include "compare/bench/bench_format.h"
#include "compare/metrics/flip.h"
#include "compare/report/report.h"
#include "scenes/cameras.h"
#include "scenes/default_light.h"

namespace mrr {

const std::vector<double>& foveaRingEdges() {
  static const std::vector<double> edges = {0.0, 2.0, 5.0, 10.0, 20.0, 30.0};
  return edges;
}

int foveaRing(int dx, int dy, double ppd) {
  const double e = std::sqrt(static_cast<double>(dx) * dx + static_cast<double>(dy) * dy) / ppd;
  const std::vector<double>& edges = foveaRingEdges();
  int ring = 0;
  for (size_t i = 1; i < edges.size(); ++i)
    if (e >= edges[i]) ring = static_cast<int>(i);
  return ring;
}

namespace {

using bench_format::fixed;
using bench_format::sci;
using bench_format::sizeName;

// The method's own time, as the other groups measure it (effectMs, docs/spec.md §10).
double effectMsOf(const FrameResult& f) { return effectMs(stageMs(f)); }

int samplesOf(const BenchOptions& o, Effect e) {
  if (o.foveaSamples > 0) return o.foveaSamples;
  return e == Effect::Ssm ? 196 : e == Effect::Ssgi ? 288 : 64;
}

// A variant: a method of SPEC §9 with the level limit's terms set.
struct Variant {
  std::string name;
  Settings settings;
};

// Renders every variant `repeats` times after a warm-up, alternating; the last repeat's frames and
// the median times, by variant.
struct Measured {
  std::vector<FrameResult> frames;
  std::vector<double> effectMs;
};
Measured measureVariants(const OpenScene& sc, const Camera& camera, float framed, const std::vector<Variant>& variants,
                         int repeats) {
  Measured m;
  m.frames.resize(variants.size());
  std::vector<std::vector<double>> runs(variants.size());
  for (int i = 0; i <= repeats; ++i)
    for (size_t v = 0; v < variants.size(); ++v) {
      FrameResult f = sc.render(camera, makeConstants(variants[v].settings, framed), {false, {}, nullptr});
      if (i == 0) continue;  // warm-up
      runs[v].push_back(effectMsOf(f));
      if (i == repeats) m.frames[v] = std::move(f);
    }
  for (const std::vector<double>& r : runs) m.effectMs.push_back(median(r));
  return m;
}

// Per ring: the level pixels shaded whose sample pixel lies in it (as the report's rings count them).
std::vector<int64_t> shadedByRing(const FrameResult& f, int gx, int gy, double ppd) {
  return shadedLevelPixelsByRing(f, static_cast<int>(foveaRingEdges().size()),
                                 [&](int px, int py) { return foveaRing(px - gx, py - gy, ppd); });
}

// One scene, one ppd: every variant's rings.
void ringsOf(const BenchOptions& o, const BenchPath& path, const OpenScene& sc, Effect effect, double ppd,
             std::vector<FoveaRingRecord>& out) {
  const auto [w, h] = o.foveaSize;
  const int samples = samplesOf(o, effect);
  const int gx = w / 2, gy = h / 2;
  const float framed = framedSize(*sc.scene, sc.camera, static_cast<float>(w) / static_cast<float>(h)).size;
  std::vector<Variant> variants;
  variants.push_back({referenceMethod(), settingsFor(referenceMethod(), effect, w, h, samples)});
  for (const std::string& m : o.foveaMethods)
    for (const bool foveate : {false, true}) {
      Settings s = settingsFor(m, effect, w, h, samples);
      s.foveation.ppd = static_cast<float>(ppd);
      s.foveation.gaze = true;  // off: the gaze only measures (the method's own decisions)
      s.foveation.gazeX = gx;
      s.foveation.gazeY = gy;
      s.foveation.foveate = foveate;
      variants.push_back({foveate ? m + "+gaze" : m, s});
    }
  const Measured meas = measureVariants(sc, sc.camera, framed, variants, o.repeats);
  const FrameResult& full = meas.frames.front();
  const size_t rings = foveaRingEdges().size();
  std::vector<long long> pixels(rings, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ++pixels[static_cast<size_t>(foveaRing(x - gx, y - gy, ppd))];
  for (size_t v = 0; v < variants.size(); ++v) {
    const FrameResult& f = meas.frames[v];
    const std::vector<int64_t> shaded = shadedByRing(f, gx, gy, ppd);
    // RMS and FLIP per ring, in double, in pixel order.
    std::vector<double> sq(rings, 0.0), flipSum(rings, 0.0);
    std::vector<long long> values(rings, 0);
    const ImageF& a = f.final();
    const ImageF& b = full.final();
    const ImageF flipMap = flip(b, a, ppd).errorMap;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t r = static_cast<size_t>(foveaRing(x - gx, y - gy, ppd));
        for (int ch = 0; ch < a.channels; ++ch) {
          const double d = static_cast<double>(a.at(x, y, ch)) - static_cast<double>(b.at(x, y, ch));
          sq[r] += d * d;
          ++values[r];
        }
        flipSum[r] += static_cast<double>(flipMap.at(x, y));
      }
    for (size_t r = 0; r < rings; ++r) {
      if (pixels[r] == 0) continue;  // a ring outside the frame
      FoveaRingRecord rec;
      rec.path = path.name;
      rec.scene = sc.name;
      rec.effect = toString(effect);
      rec.method = variants[v].name;
      rec.samples = samples;
      rec.width = w;
      rec.height = h;
      rec.gazeX = gx;
      rec.gazeY = gy;
      rec.ppd = ppd;
      rec.fromDegrees = foveaRingEdges()[r];
      rec.toDegrees = r + 1 < rings ? foveaRingEdges()[r + 1] : -1.0;
      rec.pixels = pixels[r];
      rec.shadedLevelPixels = shaded[r];
      rec.shadedShare = static_cast<double>(shaded[r]) / static_cast<double>(pixels[r]);
      rec.rms = std::sqrt(sq[r] / static_cast<double>(values[r]));
      rec.flip = flipSum[r] / static_cast<double>(pixels[r]);
      rec.frameShare = static_cast<double>(f.shadedPixelsTotal) / (static_cast<double>(w) * h);
      rec.effectMs = meas.effectMs[v];
      rec.fellBack = f.fallback.fellBack;
      rec.budgeted = std::any_of(f.refinement.begin(), f.refinement.end(),
                                 [](const RefinementRecord& x) { return x.budgeted; });
      out.push_back(rec);
    }
  }
}

// The mean |v| over W×H pixels on geometry (SPEC §13 step 3's motion image, padded grid).
double meanSpeed(const FrameResult& f) {
  const Constants& c = f.constants;
  const ImageU8& hit = f.levels[0].gbuffer.hit;
  double sum = 0.0;
  long long n = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      if (!hit.at(x, y)) continue;
      sum += std::min(static_cast<double>(f.motion.at(x, y)), 1.0e4);  // a point behind the previous camera: capped
      ++n;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

// One scene, one camera path: per frame after the first, each method without and with the previous
// path frame as its previous frame.
void motionOf(const BenchOptions& o, const BenchPath& path, const OpenScene& sc, Effect effect, const std::string& kind,
              std::vector<FoveaMotionRecord>& out) {
  const auto [w, h] = o.foveaMotionSize;
  const int samples = samplesOf(o, effect);
  const float framed = framedSize(*sc.scene, sc.camera, static_cast<float>(w) / static_cast<float>(h)).size;
  const std::vector<Camera> cams = cameraPath(sc.camera, kind, o.foveaFrames);
  for (size_t t = 1; t < cams.size(); ++t) {
    std::vector<Variant> variants;
    for (const std::string& m : o.foveaMethods) {
      Settings s = settingsFor(m, effect, w, h, samples);
      variants.push_back({m, s});
      s.foveation.motion = true;
      s.foveation.prevEye = cams[t - 1].eye;
      s.foveation.prevTarget = cams[t - 1].target;
      s.foveation.prevUp = cams[t - 1].up;
      s.foveation.prevYfov = cams[t - 1].yfov;
      variants.push_back({m + "+motion", s});
    }
    const Measured meas = measureVariants(sc, cams[t], framed, variants, o.repeats);
    // The speed: from a +motion frame that has the motion image and the level-0 G-buffer (every
    // one measures the same |v|). A frame the never-slower rule shaded at full res has no motion
    // image, and the port keeps the G-buffer only with its stages: where no frame has both, the
    // first +motion variant once more, rule off, stages kept (untimed).
    const auto hasSpeed = [](const FrameResult& f) {
      const Constants& c = f.constants;
      return f.motion.width >= c.width && f.motion.height >= c.height && f.levels[0].gbuffer.hit.width >= c.width &&
             f.levels[0].gbuffer.hit.height >= c.height;
    };
    double speed = -1.0;
    for (size_t v = 0; v < variants.size() && speed < 0.0; ++v)
      if (variants[v].settings.foveation.motion && hasSpeed(meas.frames[v])) speed = meanSpeed(meas.frames[v]);
    for (size_t v = 0; v < variants.size() && speed < 0.0; ++v)
      if (variants[v].settings.foveation.motion) {
        Settings ruleOff = variants[v].settings;
        ruleOff.neverSlower = false;
        const FrameResult f = sc.render(cams[t], makeConstants(ruleOff, framed), {true, {}, nullptr});
        if (!hasSpeed(f)) throw MrrError("bench fovea: a frame with --prev-frame has no motion image");
        speed = meanSpeed(f);
      }
    for (size_t v = 0; v < variants.size(); ++v) {
      const FrameResult& f = meas.frames[v];
      FoveaMotionRecord r;
      r.path = path.name;
      r.scene = sc.name;
      r.effect = toString(effect);
      r.kind = kind;
      r.method = variants[v].name;
      r.samples = samples;
      r.width = w;
      r.height = h;
      r.frame = static_cast<int>(t);
      r.frames = o.foveaFrames;
      r.meanSpeed = speed;
      r.shadedShare = static_cast<double>(f.shadedPixelsTotal) / (static_cast<double>(w) * h);
      r.effectMs = meas.effectMs[v];
      r.fellBack = f.fallback.fellBack;
      out.push_back(r);
    }
  }
}

}  // namespace

size_t foveaSteps(const BenchOptions& o) {
  if (!o.fovea && !o.foveaOnly) return 0;
  return o.foveaScenes.size() * (o.foveaPpds.size() + (o.foveaFrames > 0 ? cameraPathKinds().size() : 0));
}

void runFoveaGroup(const BenchOptions& o, const BenchPath& path, FoveaResults& out) {
  if (!o.fovea && !o.foveaOnly) return;
  const Effect effect = parseEffect(o.foveaEffect);
  const auto start = std::chrono::steady_clock::now();
  size_t done = 0;
  const size_t total = foveaSteps(o);
  const auto step = [&](const std::string& what) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cerr << "[bench] fovea " << ++done << "/" << total << "  " << path.name << " " << what << "  (" << fixed(s, 0)
              << " s)\n";
  };
  for (const std::string& sceneName : o.foveaScenes) {
    const OpenScene sc = openScene(sceneName, path);
    for (double ppd : o.foveaPpds) {
      step(sceneName + " rings at ppd " + fixed(ppd, 2) + ", " + sizeName(o.foveaSize.first, o.foveaSize.second));
      ringsOf(o, path, sc, effect, ppd, out.rings);
    }
    if (o.foveaFrames > 0)
      for (const std::string& kind : cameraPathKinds()) {
        step(sceneName + " motion along the " + kind + ", " + std::to_string(o.foveaFrames) + " frames, " +
             sizeName(o.foveaMotionSize.first, o.foveaMotionSize.second));
        motionOf(o, path, sc, effect, kind, out.motion);
      }
  }
}

std::string foveaMarkdown(const FoveaResults& res) {
  std::ostringstream o;
  if (!res.rings.empty()) {
    o << "### Foveation: per eccentricity ring, gaze at the image centre (SPEC §13)\n\n"
      << "Share: level pixels shaded whose sample pixel is in the ring / the ring's full-res pixels (1 = full). RMS and "
         "mean FLIP (at the ring's ppd): the effect buffer against `full`, over the ring. A method without `+gaze` has "
         "the gaze measuring only (`--foveate off`), its own decisions. ms: the frame's time less its full-res "
         "G-buffer, median of the repeats (the whole frame, the same in every ring).\n\n"
      << "| path | scene | size | effect | ppd | method | ring | pixels | share | RMS | FLIP | frame share | ms | fell back |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const FoveaRingRecord& r : res.rings)
      o << "| " << r.path << " | " << r.scene << " | " << sizeName(r.width, r.height) << " | " << r.effect << "-" << r.samples
        << " | " << fixed(r.ppd, 2) << " | " << r.method << " | "
        << (r.toDegrees < 0 ? "> " + fixed(r.fromDegrees, 0) + "°" : fixed(r.fromDegrees, 0) + "–" + fixed(r.toDegrees, 0) + "°")
        << " | " << r.pixels << " | " << fixed(r.shadedShare, 3) << " | " << sci(r.rms) << " | " << sci(r.flip) << " | "
        << fixed(r.frameShare, 3) << " | " << fixed(r.effectMs, 1) << " | " << (r.fellBack ? "yes" : "") << " |\n";
    o << "\n";
  }
  if (!res.motion.empty()) {
    o << "### Motion: shaded share against screen speed along the camera paths (SPEC §13)\n\n"
      << "Each frame of the path after the first, with the path's previous frame as `--prev-frame` (`+motion`) and "
         "without. Speed: mean |v| over the pixels on geometry, full-res pixels per frame. ms: median of the repeats.\n\n"
      << "| path | scene | size | effect | camera path | frame | speed (px) | method | share | ms | fell back |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const FoveaMotionRecord& r : res.motion)
      o << "| " << r.path << " | " << r.scene << " | " << sizeName(r.width, r.height) << " | " << r.effect << "-" << r.samples
        << " | " << r.kind << " | " << r.frame << "/" << r.frames << " | " << fixed(r.meanSpeed, 2) << " | " << r.method
        << " | " << fixed(r.shadedShare, 3) << " | " << fixed(r.effectMs, 1) << " | " << (r.fellBack ? "yes" : "") << " |\n";
    o << "\n";
  }
  return o.str();
}

nlohmann::json foveaJson(const FoveaResults& res) {
  nlohmann::json rings = nlohmann::json::array(), motion = nlohmann::json::array();
  for (const FoveaRingRecord& r : res.rings)
    rings.push_back({{"path", r.path}, {"scene", r.scene}, {"effect", r.effect}, {"samples", r.samples},
                     {"width", r.width}, {"height", r.height}, {"ppd", r.ppd}, {"gaze", {r.gazeX, r.gazeY}},
                     {"method", r.method}, {"from_degrees", r.fromDegrees},
                     {"to_degrees", r.toDegrees < 0 ? nlohmann::json(nullptr) : nlohmann::json(r.toDegrees)},
                     {"pixels", r.pixels}, {"shaded_level_pixels", r.shadedLevelPixels}, {"shaded_share", r.shadedShare},
                     {"rms", r.rms}, {"flip", r.flip}, {"frame_share", r.frameShare}, {"effect_ms", r.effectMs},
                     {"fell_back_to_full", r.fellBack}});
  for (const FoveaMotionRecord& r : res.motion)
    motion.push_back({{"path", r.path}, {"scene", r.scene}, {"effect", r.effect}, {"samples", r.samples},
                      {"width", r.width}, {"height", r.height}, {"camera_path", r.kind}, {"frame", r.frame},
                      {"frames", r.frames}, {"method", r.method}, {"mean_speed", r.meanSpeed},
                      {"shaded_share", r.shadedShare}, {"effect_ms", r.effectMs}, {"fell_back_to_full", r.fellBack}});
  return {{"ring_edges_degrees", foveaRingEdges()}, {"rings", rings}, {"motion", motion}};
}

std::string foveaRingsCsv(const FoveaResults& res) {
  std::ostringstream o;
  o << "path,scene,effect,samples,width,height,ppd,gaze_x,gaze_y,method,from_degrees,to_degrees,pixels,"
       "shaded_level_pixels,shaded_share,rms,flip,frame_share,effect_ms,fell_back\n";
  for (const FoveaRingRecord& r : res.rings)
    o << r.path << "," << r.scene << "," << r.effect << "," << r.samples << "," << r.width << "," << r.height << ","
      << r.ppd << "," << r.gazeX << "," << r.gazeY << "," << r.method << "," << r.fromDegrees << ","
      << (r.toDegrees < 0 ? std::string("inf") : fixed(r.toDegrees, 0)) << "," << r.pixels << "," << r.shadedLevelPixels
      << "," << r.shadedShare << "," << r.rms << "," << r.flip << "," << r.frameShare << "," << r.effectMs << ","
      << (r.fellBack ? 1 : 0) << "\n";
  return o.str();
}

std::string foveaMotionCsv(const FoveaResults& res) {
  std::ostringstream o;
  o << "path,scene,effect,samples,width,height,camera_path,frame,frames,method,mean_speed,shaded_share,effect_ms,"
       "fell_back\n";
  for (const FoveaMotionRecord& r : res.motion)
    o << r.path << "," << r.scene << "," << r.effect << "," << r.samples << "," << r.width << "," << r.height << ","
      << r.kind << "," << r.frame << "," << r.frames << "," << r.method << "," << r.meanSpeed << "," << r.shadedShare
      << "," << r.effectMs << "," << (r.fellBack ? 1 : 0) << "\n";
  return o.str();
}

std::string foveaCsvPath(const std::string& csvPath, const std::string& suffix) {
  const std::filesystem::path p(csvPath);
  return (p.parent_path() / (p.stem().string() + suffix + ".csv")).string();
}

std::vector<std::string> foveaSanityChecks(const FoveaResults& res) {
  std::vector<std::string> fails;
  std::map<std::string, const FoveaRingRecord*> byKey;
  const auto key = [](const FoveaRingRecord& r, const std::string& method) {
    return r.path + " " + r.scene + " ppd " + fixed(r.ppd, 2) + " ring " + fixed(r.fromDegrees, 0) + " " + method;
  };
  for (const FoveaRingRecord& r : res.rings) byKey[key(r, r.method)] = &r;
  for (const FoveaRingRecord& r : res.rings) {
    const std::string where = "fovea " + key(r, r.method);
    if (!std::isfinite(r.rms) || !(r.flip >= 0.0 && r.flip <= 1.0) || !(r.shadedShare >= 0.0))
      fails.push_back(where + ": figures not finite or FLIP outside [0,1]");
    if (r.method == referenceMethod() && (r.rms != 0.0 || r.shadedShare != 1.0))
      fails.push_back(where + ": full's error is not 0 or it does not shade every pixel");
    // a gaze never adds a level pixel, except where a budget (SPEC §12.4) spends the time it frees
    const size_t plus = r.method.rfind("+gaze");
    if (plus != std::string::npos && !r.fellBack && !r.budgeted) {
      const auto own = byKey.find(key(r, r.method.substr(0, plus)));
      if (own != byKey.end() && !own->second->fellBack && r.shadedLevelPixels > own->second->shadedLevelPixels)
        fails.push_back(where + ": shades " + std::to_string(r.shadedLevelPixels) + " level pixels, more than without the gaze (" +
                        std::to_string(own->second->shadedLevelPixels) + ")");
    }
  }
  for (const FoveaMotionRecord& r : res.motion)
    if (!std::isfinite(r.meanSpeed) || r.meanSpeed < 0.0 || !(r.shadedShare >= 0.0))
      fails.push_back("fovea motion " + r.scene + " " + r.kind + " frame " + std::to_string(r.frame) + " " + r.method +
                      ": speed or share not finite");
  return fails;
}

}  // namespace mrr
