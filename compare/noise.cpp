#include "compare/noise.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/stages.h"
#include "common/tolerance.h"

namespace mrr {

bool isStochastic(Effect effect) { return effect == Effect::Ssao || effect == Effect::Ssgi; }

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
  // Per pixel and channel: the seeds' mean and variance.
  std::vector<double> mean(n * ch, 0.0), var(n * ch, 0.0), top(n * ch, 0.0);
  double scaleSum = 0.0;
  int64_t scaleCount = 0;
  for (size_t i = 0; i < n * ch; ++i) {
    if (!include[i / ch]) continue;
    double m = 0.0, mx = 0.0;
    for (const ImageF& s : seeds) {
      m += s.data[i];
      mx = std::max(mx, std::fabs(static_cast<double>(s.data[i])));
    }
    m /= k;
    double ss = 0.0;
    for (const ImageF& s : seeds) ss += (s.data[i] - m) * (s.data[i] - m);
    mean[i] = m;
    var[i] = ss / (k - 1.0);
    top[i] = mx;
    scaleSum += std::fabs(m);
    ++scaleCount;
  }
  const double frameScale = scaleCount ? scaleSum / static_cast<double>(scaleCount) : 0.0;
  // 1. Per pixel: Welch's t of the subject's one value (its variance the seeds', df K − 1) against
  // the seeds' mean (variance s²/K, df K − 1), each spread at least one sample's worth.
  for (size_t p = 0; p < n; ++p) f.pixels += include[p] != 0;
  f.tests = f.pixels * static_cast<int64_t>(ch);
  f.pixelLevel = sidakLevel(rule.pixelAlpha, std::max<int64_t>(f.tests, 1));
  double worstP = 2.0;
  for (size_t p = 0; p < n; ++p) {
    if (!include[p]) continue;
    bool rejected = false;
    for (size_t c = 0; c < ch; ++c) {
      const size_t i = p * ch + c;
      const double floorSd = rule.sampleFloor * std::max(top[i], frameScale) / std::max(samples, 1);
      const double own = var[i] + floorSd * floorSd;
      const WelchResult w = welchTest(subject.data[i], own, k - 1.0, mean[i], own / k, k - 1.0);
      rejected = rejected || w.p < f.pixelLevel;
      if (w.p < worstP || (w.p == worstP && std::fabs(w.t) > std::fabs(f.worstT))) {
        worstP = w.p;
        f.worstP = w.p;
        f.worstT = w.t;
        f.worstX = static_cast<int>(p % static_cast<size_t>(subject.width));
        f.worstY = static_cast<int>(p / static_cast<size_t>(subject.width));
        f.worstChannel = static_cast<int>(c);
        f.worstValue = subject.data[i];
        f.worstMean = mean[i];
        const double half = studentTCritical(f.pixelLevel, w.df) * std::sqrt(own + own / k);
        f.worstLo = mean[i] - half;
        f.worstHi = mean[i] + half;
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

std::string describeNoisePixel(const FrameResult& oracle, const FrameResult& subject, const NoiseReference& reference,
                               int x, int y) {
  std::string out = "noise-aware: the stochastic stages at " + std::to_string(x) + "," + std::to_string(y) +
                    " against the oracle's " + std::to_string(reference.seeds) + " seeds (docs/spec.md 8)\n";
  for (const auto& [stage, image] : stochasticImages(subject)) {
    const auto seeds = reference.stages.find(stage);
    if (seeds == reference.stages.end() || seeds->second.empty()) continue;
    const size_t at = stage.find(".L");
    const int level = at == std::string::npos ? -1 : std::stoi(stage.substr(at + 2));
    const int scale = level < 0 ? 1 : oracle.constants.levels[static_cast<size_t>(level)].scale;
    const int lx = x / scale, ly = y / scale;
    char text[400];
    if (lx >= image->width || ly >= image->height) continue;
    const size_t p = static_cast<size_t>(ly) * image->width + lx;
    if (level >= 0) {
      const ImageU8& s = oracle.levels[static_cast<size_t>(level)].masks.stencil;
      if (s.data.size() == image->pixelCount() && !s.data[p]) {
        std::snprintf(text, sizeof text, "  %-8s not shaded at level pixel %d,%d\n", stage.c_str(), lx, ly);
        out += text;
        continue;
      }
    }
    std::vector<char> one(image->pixelCount(), 0);
    one[p] = 1;
    const NoiseFigures f = noiseTest(*image, seeds->second, one, {}, reference.samples);
    const bool inside = f.worstValue >= f.worstLo && f.worstValue <= f.worstHi;
    std::snprintf(text, sizeof text,
                  "  %-8s %.6g; the oracle's mean %.6g, one draw in [%.6g, %.6g] (%.3g%%, this pixel alone): %s, t = %.3g%s\n",
                  stage.c_str(), f.worstValue, f.worstMean, f.worstLo, f.worstHi, 100.0 * (1.0 - f.pixelLevel),
                  inside ? "inside" : "OUTSIDE", f.worstT,
                  image->channels > 1 ? (" (channel " + std::to_string(f.worstChannel) + ", the farthest)").c_str() : "");
    out += text;
  }
  return out;
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
