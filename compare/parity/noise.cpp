#include "compare/parity/noise.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/stages.h"
#include "common/tolerance.h"

namespace mrr {

namespace {

// The stochastic stages of a frame, by name, as the parity rows name them.
std::vector<std::pair<std::string, const ImageF*>> stochasticImages(const FrameResult& f) {
  std::vector<std::pair<std::string, const ImageF*>> out;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelResult& lr = f.levels[static_cast<size_t>(l)];
    if (!lr.raw.data.empty()) out.emplace_back(partName(Part::Raw, l), &lr.raw);
    if (!lr.sub.data.empty()) out.emplace_back(partName(Part::Sub, l), &lr.sub);
  }
  if (!f.final().data.empty()) out.emplace_back(partName(Part::Final), &f.final());
  if (!f.shaded.data.empty()) out.emplace_back(partName(Part::Shaded), &f.shaded);
  return out;
}

const ImageF* stageImage(const FrameResult& f, const std::string& stage) {
  for (const auto& [name, image] : stochasticImages(f))
    if (name == stage) return image;
  return nullptr;
}

// The subject's and the oracle's stencils both set (a level stage), or every pixel that hits
// geometry in the oracle's level-0 G-buffer (a full-res stage: the sky is no estimate).
std::vector<char> includedPixels(const FrameResult& oracle, const FrameResult& subject, int level, const ImageF& image) {
  std::vector<char> in(image.pixelCount(), 0);
  if (level >= 0) {
    const ImageU8& a = oracle.levels[static_cast<size_t>(level)].masks.stencil;
    const ImageU8& b = subject.levels[static_cast<size_t>(level)].masks.stencil;
    for (size_t i = 0; i < in.size(); ++i)
      in[i] = (a.data.size() == in.size() ? a.data[i] != 0 : true) && (b.data.size() == in.size() ? b.data[i] != 0 : true);
    return in;
  }
  const ImageU8& hit = oracle.levels[0].gbuffer.hit;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      in[static_cast<size_t>(y) * image.width + x] = x < hit.width && y < hit.height ? hit.at(x, y) != 0 : 1;
  return in;
}

// The regions whose bias is tested: the frame, the edge band, each level's stencil.
std::vector<NoiseRegion> regionsOf(const FrameResult& oracle, int level, const ImageF& image, const std::vector<char>& in) {
  std::vector<NoiseRegion> regions = {{"the frame", in}};
  const int w = image.width, h = image.height;
  auto add = [&](std::string name, const std::function<bool(int, int)>& inside) {
    NoiseRegion r{std::move(name), std::vector<char>(in.size(), 0)};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = static_cast<size_t>(y) * w + x;
        r.mask[i] = in[i] && inside(x, y);
      }
    regions.push_back(std::move(r));
  };
  if (level >= 0) {
    // The edge band of the level: its max-pooled edges M_ℓ.
    const ImageU8& m = oracle.levels[static_cast<size_t>(level)].masks.mask;
    if (m.width == w && m.height == h) add("the edge band (M_" + std::to_string(level) + ")", [&](int x, int y) { return m.at(x, y) != 0; });
    return regions;
  }
  // Full res: the edges E widened by 2 px, and each level's share of the blend (the level map).
  const ImageU8& e = oracle.edges.combined;
  if (!e.data.empty()) {
    add("the edge band (E + 2 px)", [&](int x, int y) {
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const int u = x + dx, v = y + dy;
          if (u >= 0 && v >= 0 && u < e.width && v < e.height && e.at(u, v)) return true;
        }
      return false;
    });
  }
  const ImageU8& map = oracle.blend.levelMap;
  if (map.width == w && map.height == h)
    for (int l = 0; l < kLevelCount; ++l)
      if (oracle.constants.levels[static_cast<size_t>(l)].enabled)
        add("level " + std::to_string(l) + "'s pixels", [&, l](int x, int y) { return map.at(x, y) == l; });
  return regions;
}

// One pixel-channel's statistics over the K seeds: their mean, their variance, the largest |value|.
struct SeedStats {
  double mean = 0.0, var = 0.0, top = 0.0;
};

SeedStats seedStats(const std::vector<ImageF>& seeds, size_t i) {
  SeedStats st;
  const double k = static_cast<double>(seeds.size());
  for (const ImageF& s : seeds) {
    st.mean += s.data[i];
    st.top = std::max(st.top, std::fabs(static_cast<double>(s.data[i])));
  }
  st.mean /= k;
  double ss = 0.0;
  for (const ImageF& s : seeds) ss += (s.data[i] - st.mean) * (s.data[i] - st.mean);
  st.var = ss / (k - 1.0);
  return st;
}

// What one sample may be worth on the stage: the largest |value| any seed shows at any included
// pixel and channel. A pixel's value is a mean of N samples, so a sample brighter than the
// brightest pixel seen exists; where the K seeds happen to draw none, SSGI's heavy-tailed samples
// (a lit surface reached once) would otherwise look like a bug.
double sampleScaleOf(const std::vector<ImageF>& seeds, const std::vector<char>& include, size_t channels) {
  double top = 0.0;
  for (const ImageF& s : seeds)
    for (size_t i = 0; i < include.size() * channels; ++i)
      if (include[i / channels]) top = std::max(top, std::fabs(static_cast<double>(s.data[i])));
  return top;
}

// One draw's variance at a pixel: the seeds' own, plus one sample's worth (kNoiseRule.sampleFloor
// samples of the stage's sample scale, over N), so that a pixel whose seeds barely vary does not
// reject a rare sample.
double drawVariance(const SeedStats& st, double sampleScale, int samples) {
  const double floorSd = kNoiseRule.sampleFloor * std::max(st.top, sampleScale) / std::max(samples, 1);
  return st.var + floorSd * floorSd;
}

// The per-pixel test: Welch's t of the subject's one value (its variance one draw's, df K − 1)
// against the seeds' mean (variance one draw's / K, df K − 1).
WelchResult pixelTest(double value, const SeedStats& st, double own, double k) {
  return welchTest(value, own, k - 1.0, st.mean, own / k, k - 1.0);
}

// The half-width of the interval one draw is accepted in at the per-test level `level`.
double acceptedHalfWidth(const WelchResult& w, double own, double k, double level) {
  return studentTCritical(level, w.df) * std::sqrt(own + own / k);
}

}  // namespace

NoiseReference buildNoiseReference(const std::function<FrameResult(uint32_t seed)>& render, int samples,
                                   const std::function<void(int, int)>& progress) {
  NoiseReference ref;
  ref.seeds = kNoiseRule.seeds;
  ref.samples = samples;
  for (int k = 0; k < kNoiseRule.seeds; ++k) {
    if (progress) progress(k, kNoiseRule.seeds);
    const FrameResult f = render(kNoiseRule.firstSeed + static_cast<uint32_t>(k));
    for (const auto& [name, image] : stochasticImages(f)) ref.stages[name].push_back(*image);
  }
  return ref;
}

NoiseFigures noiseTest(const ImageF& subject, const std::vector<ImageF>& seeds, const std::vector<char>& include,
                       const std::vector<NoiseRegion>& regions, int samples) {
  const NoiseRule& rule = kNoiseRule;
  NoiseFigures f;
  const int K = static_cast<int>(seeds.size());
  f.seeds = K;
  const size_t n = subject.pixelCount(), ch = static_cast<size_t>(subject.channels);
  for (const ImageF& s : seeds)
    require(s.width == subject.width && s.height == subject.height && s.channels == subject.channels,
            "internal: the noise reference's stage differs in size from the subject's");
  require(K >= 3, "internal: the noise test needs at least 3 seeds");
  const double k = K;
  const double sampleScale = sampleScaleOf(seeds, include, ch);
  // 1. Per pixel: Welch's t against the seeds' mean, each spread at least one sample's worth.
  for (size_t p = 0; p < n; ++p) f.pixels += include[p] != 0;
  f.tests = f.pixels * static_cast<int64_t>(ch);
  f.pixelLevel = sidakLevel(rule.pixelAlpha, std::max<int64_t>(f.tests, 1));
  std::vector<double> mean(n * ch, 0.0);
  double worstP = 2.0;
  for (size_t p = 0; p < n; ++p) {
    if (!include[p]) continue;
    bool rejected = false;
    for (size_t c = 0; c < ch; ++c) {
      const size_t i = p * ch + c;
      const SeedStats st = seedStats(seeds, i);
      mean[i] = st.mean;
      const double own = drawVariance(st, sampleScale, samples);
      const WelchResult w = pixelTest(subject.data[i], st, own, k);
      rejected = rejected || w.p < f.pixelLevel;
      if (w.p < worstP || (w.p == worstP && std::fabs(w.t) > std::fabs(f.worstT))) {
        worstP = w.p;
        f.worstP = w.p;
        f.worstT = w.t;
        f.worstX = static_cast<int>(p % static_cast<size_t>(subject.width));
        f.worstY = static_cast<int>(p / static_cast<size_t>(subject.width));
        f.worstChannel = static_cast<int>(c);
        f.worstValue = subject.data[i];
        f.worstMean = st.mean;
        const double half = acceptedHalfWidth(w, own, k, f.pixelLevel);
        f.worstLo = st.mean - half;
        f.worstHi = st.mean + half;
      }
    }
    f.rejected += rejected;
  }
  f.shareRejected = f.pixels ? static_cast<double>(f.rejected) / static_cast<double>(f.pixels) : 0.0;
  // 2. The bias of each region: the subject's against the spread of the seeds' own biases
  // (each seed against the mean of the others), which keeps what the pixels share (one kernel
  // per frame) in the spread.
  std::vector<const NoiseRegion*> tested;
  for (const NoiseRegion& r : regions)
    if (std::count(r.mask.begin(), r.mask.end(), char{1}) >= rule.minRegionPixels) tested.push_back(&r);
  const double biasLevel = sidakLevel(rule.biasAlpha, std::max<int64_t>(static_cast<int64_t>(tested.size()), 1));
  const double tCrit = studentTCritical(biasLevel, k - 1.0);
  for (const NoiseRegion* r : tested) {
    RegionBias b;
    b.region = r->name;
    double sumMean = 0.0, sumSubject = 0.0, sumAbs = 0.0;
    std::vector<double> sumSeed(seeds.size(), 0.0);
    for (size_t p = 0; p < n; ++p) {
      if (!r->mask[p]) continue;
      ++b.pixels;
      for (size_t c = 0; c < ch; ++c) {
        const size_t i = p * ch + c;
        sumMean += mean[i];
        sumAbs += std::fabs(mean[i]);
        sumSubject += subject.data[i];
        for (size_t s = 0; s < seeds.size(); ++s) sumSeed[s] += seeds[s].data[i];
      }
    }
    const double count = static_cast<double>(b.pixels) * static_cast<double>(ch);
    b.relative = sumAbs > 1e-6 * count;
    const double norm = b.relative ? sumMean : count;
    b.bias = (sumSubject - sumMean) / norm;
    std::vector<double> seedBias;
    for (double s : sumSeed) {
      const double others = (k * sumMean - s) / (k - 1.0);
      seedBias.push_back((s - others) / (b.relative ? others : count));
    }
    double ss = 0.0;
    for (double v : seedBias) ss += v * v;  // their mean is 0 by construction
    b.seedSpread = std::sqrt(ss / (k - 1.0));
    // A seed's bias is against the mean of K − 1 others, the subject's against the mean of K.
    const double se = b.seedSpread * std::sqrt((1.0 + 1.0 / k) / (1.0 + 1.0 / (k - 1.0)));
    b.lo = b.bias - tCrit * se;
    b.hi = b.bias + tCrit * se;
    b.pass = (b.lo <= 0.0 && b.hi >= 0.0) || (b.relative && std::fabs(b.bias) <= rule.biasFloor);
    f.biases.push_back(b);
  }
  return f;
}

bool NoisePixel::inside() const {
  for (const NoisePixelStage& s : stages)
    for (const NoiseChannel& c : s.channels)
      if (s.shaded && !c.inside) return false;
  return true;
}

NoisePixel noisePixel(const FrameResult& oracle, const FrameResult& subject, const NoiseReference& reference, int x, int y) {
  NoisePixel out;
  out.x = x;
  out.y = y;
  out.seeds = reference.seeds;
  out.samples = reference.samples;
  out.firstSeed = kNoiseRule.firstSeed;
  for (const auto& [stage, image] : stochasticImages(subject)) {
    const auto seeds = reference.stages.find(stage);
    if (seeds == reference.stages.end() || seeds->second.size() < 3) continue;
    NoisePixelStage st;
    st.stage = stage;
    const size_t at = stage.find(".L");
    st.level = at == std::string::npos ? -1 : std::stoi(stage.substr(at + 2));
    Part part;
    if (partOf(stage, part)) st.shader = std::string(partInfo(part).shader);
    if (st.shader.find(' ') != std::string::npos) st.shader = toString(oracle.constants.effect) + ".frag";  // raw: the effect's
    const int scale = st.level < 0 ? 1 : oracle.constants.levels[static_cast<size_t>(st.level)].scale;
    st.x = x / scale;
    st.y = y / scale;
    if (st.x >= image->width || st.y >= image->height) continue;
    const size_t p = static_cast<size_t>(st.y) * image->width + st.x;
    // The verdict's family: the stage's tested pixels, as compare --noise-aware takes them.
    const std::vector<char> in = includedPixels(oracle, subject, st.level, *image);
    const size_t ch = static_cast<size_t>(image->channels);
    st.stagePixels = std::count(in.begin(), in.end(), char{1});
    st.pixelLevel = sidakLevel(kNoiseRule.pixelAlpha, std::max<int64_t>(st.stagePixels * static_cast<int64_t>(ch), 1));
    st.shaded = in[p] != 0;
    if (st.shaded) {
      const double k = static_cast<double>(seeds->second.size());
      const double sampleScale = sampleScaleOf(seeds->second, in, ch);
      double farthest = -1.0;
      for (size_t c = 0; c < ch; ++c) {
        const size_t i = p * ch + c;
        const SeedStats s = seedStats(seeds->second, i);
        NoiseChannel nc;
        nc.value = image->data[i];
        nc.mean = s.mean;
        std::vector<double> values;
        for (const ImageF& seed : seeds->second) values.push_back(seed.data[i]);
        const MeanInterval m = meanInterval(values, 0.95);
        nc.meanLo = m.lo;
        nc.meanHi = m.hi;
        const double own = drawVariance(s, sampleScale, reference.samples);
        nc.sd = std::sqrt(own);
        const WelchResult w = pixelTest(nc.value, s, own, k);
        nc.t = w.t;
        nc.p = w.p;
        const double half = acceptedHalfWidth(w, own, k, st.pixelLevel);
        nc.lo = s.mean - half;
        nc.hi = s.mean + half;
        nc.halfWidths = half > 0.0 ? std::fabs(nc.value - s.mean) / half : (nc.value == s.mean ? 0.0 : INFINITY);
        nc.inside = w.p >= st.pixelLevel;  // the verdict's own test: the same as lo ≤ value ≤ hi
        if (nc.halfWidths > farthest) {
          farthest = nc.halfWidths;
          st.farthest = static_cast<int>(c);
        }
        st.channels.push_back(nc);
      }
    }
    out.stages.push_back(std::move(st));
  }
  return out;
}

namespace {

std::string number(double v, const char* format = "%.4g") {
  char text[48];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// "inside, 0.31 of the way to the edge" / "OUTSIDE, 2.4 half-widths below the mean".
std::string whereItFalls(const NoiseChannel& c) {
  if (c.inside) return "inside (" + number(c.halfWidths, "%.2f") + " of the half-width from the mean)";
  return "OUTSIDE (" + number(c.halfWidths, "%.3g") + " half-widths " + (c.value < c.mean ? "below" : "above") +
         " the mean)";
}

}  // namespace

std::string formatNoisePixel(const NoisePixel& px, const std::string& whose) {
  std::string out = "noise-aware: pixel " + std::to_string(px.x) + "," + std::to_string(px.y) + ", each stochastic stage against the oracle's " +
                    std::to_string(px.seeds) + " frames with independent seeds (--seed " + std::to_string(px.firstSeed) +
                    "..." + std::to_string(px.firstSeed + static_cast<uint32_t>(px.seeds) - 1) + ", " +
                    std::to_string(px.samples) + " samples a pixel; docs/spec.md §8)\n";
  out += "  mean: the seeds' mean here, +- its 95% t interval; sd: one draw's spread (the seeds', at least one sample's "
         "worth);\n  accepted: where compare --noise-aware accepts one draw, Welch's t at the stage's Sidak level "
         "(1% false alarms over its pixels);\n  t: " + whose + " value's distance from the mean in draws' sd\n";
  size_t name = 6, value = 8;
  for (const NoisePixelStage& s : px.stages) name = std::max(name, s.stage.size() + s.shader.size() + 3);
  char line[512];
  auto row = [&](const std::string& a, const std::string& b, const std::string& c, const std::string& d,
                 const std::string& e, const std::string& f, const std::string& g, const std::string& h) {
    std::snprintf(line, sizeof line, "  %-*s %-9s %-*s %-19s %-9s %-34s %-7s %s", static_cast<int>(name), a.c_str(),
                  b.c_str(), static_cast<int>(value + 2), c.c_str(), d.c_str(), e.c_str(), f.c_str(), g.c_str(), h.c_str());
    std::string text = line;
    text.erase(text.find_last_not_of(' ') + 1);
    out += text + "\n";
  };
  const std::string valueHead = whose == "the port's" ? "port" : whose == "the file's" ? "file" : "value";
  row("stage", "pixel", valueHead, "mean +- 95%", "sd", "accepted (Sidak level, pixels)", "t", "where it falls");
  std::vector<std::string> outside;
  for (const NoisePixelStage& s : px.stages) {
    const std::string label = s.stage + " (" + s.shader + ")";
    const std::string where = std::to_string(s.x) + "," + std::to_string(s.y);
    if (!s.shaded) {
      row(label, where, "-", "", "", "", "",
          s.level >= 0 ? "not shaded here: level " + std::to_string(s.level) + "'s stencil leaves it to another level"
                       : "the background: no estimate");
      continue;
    }
    const NoiseChannel& c = s.channels[static_cast<size_t>(s.farthest)];
    const std::string channel = s.channels.size() > 1 ? " [channel " + std::to_string(s.farthest) + ", the farthest]" : "";
    row(label, where, number(c.value), number(c.mean) + " +- " + number(0.5 * (c.meanHi - c.meanLo), "%.2g"),
        number(c.sd, "%.3g"),
        "[" + number(c.lo) + ", " + number(c.hi) + "] (" + number(s.pixelLevel, "%.1e") + ", " +
            std::to_string(s.stagePixels) + ")",
        number(c.t, "%+.3g"), whereItFalls(c) + channel);
    if (!c.inside) outside.push_back(s.stage);
  }
  if (outside.empty()) {
    out += "at this pixel " + whose + " values lie inside every accepted interval: as far as this pixel shows, a draw of "
           "the oracle's estimator\n";
  } else {
    std::string list;
    for (const std::string& s : outside) list += (list.empty() ? "" : ", ") + s;
    out += "at this pixel " + whose + " value lies OUTSIDE the accepted interval at " + list +
           ": compare --noise-aware rejects this pixel there\n";
  }
  out += "(one pixel's interval is wide: it must hold every correct pixel of the frame; a shift of a few per cent "
         "shows in compare --noise-aware's bias over the frame and its regions, not at one pixel)\n";
  return out;
}

nlohmann::json noisePixelJson(const NoisePixel& px) {
  nlohmann::json stages = nlohmann::json::array();
  for (const NoisePixelStage& s : px.stages) {
    nlohmann::json channels = nlohmann::json::array();
    for (const NoiseChannel& c : s.channels)
      channels.push_back({{"value", c.value}, {"mean", c.mean}, {"mean_interval_95", {c.meanLo, c.meanHi}}, {"sd", c.sd},
                          {"accepted", {c.lo, c.hi}}, {"t", c.t}, {"p", c.p},
                          {"half_widths", std::isfinite(c.halfWidths) ? nlohmann::json(c.halfWidths) : nlohmann::json()},
                          {"inside", c.inside}});
    stages.push_back({{"stage", s.stage}, {"shader", s.shader}, {"level", s.level}, {"pixel", {s.x, s.y}},
                      {"shaded", s.shaded}, {"stage_pixels", s.stagePixels}, {"sidak_level", s.pixelLevel},
                      {"farthest_channel", s.farthest}, {"channels", channels}});
  }
  return {{"pixel", {px.x, px.y}},
          {"seeds", px.seeds},
          {"first_seed", px.firstSeed},
          {"samples", px.samples},
          {"interval",
           "accepted: where compare --noise-aware accepts one draw (Welch's t of the value against the seeds' mean, at "
           "the stage's Sidak level: a 1% family-wise false-alarm rate over its pixels x channels); mean_interval_95: "
           "the t interval of the seeds' mean"},
          {"inside", px.inside()},
          {"stages", stages}};
}

void applyNoiseAware(ParityResult& result, const FrameResult& oracle, const FrameResult& subject,
                     const NoiseReference& reference) {
  for (StageRow& row : result.rows) {
    const auto seeds = reference.stages.find(row.stage);
    if (seeds == reference.stages.end()) continue;
    const ImageF* image = stageImage(subject, row.stage);
    if (!image || seeds->second.empty()) continue;
    const std::vector<char> in = includedPixels(oracle, subject, row.level, *image);
    NoiseFigures figures = noiseTest(*image, seeds->second, in, regionsOf(oracle, row.level, *image, in), reference.samples);
    figures.scale = std::max(row.scale, 1);
    StageCheck check;
    check.rule = "noise";
    check.pass = figures.pass();
    // The columns of the table: pixels tested, the largest |Δ| from the seeds' mean, the share
    // rejected; the worst pixel is the one with the smallest p.
    DiffFigures& d = check.figures;
    d.pixels = figures.pixels;
    d.over = figures.rejected;
    d.shareOver = figures.shareRejected;
    d.worstX = figures.worstX;
    d.worstY = figures.worstY;
    d.maxAbs = std::fabs(figures.worstValue - figures.worstMean);
    d.rms = figures.biases.empty() ? 0.0 : std::fabs(figures.biases.front().bias);
    check.noise = std::move(figures);
    const bool isRaw = row.stage.rfind(partName(Part::Raw, 0).substr(0, 4), 0) == 0;  // "raw."
    row.endToEnd = std::move(check);
    if (isRaw) row.sameInput.reset();  // mrr's own sampling on the subject's inputs: not the subject's estimator
  }
}

}  // namespace mrr
