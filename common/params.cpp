#include "common/params.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/error.h"
#include "common/frame_params.h"
#include "common/kernels.h"

namespace mrr {

std::string toString(Effect effect) {
  switch (effect) {
    case Effect::Ssao: return "ssao";
    case Effect::Ssm: return "ssm";
    case Effect::Ssgi: return "ssgi";
  }
  return "?";
}

Effect parseEffect(const std::string& name) {
  if (name == "ssao") return Effect::Ssao;
  if (name == "ssm") return Effect::Ssm;
  if (name == "ssgi") return Effect::Ssgi;
  throw MrrError(optionName(Param::Effect) + " " + name + ": unknown effect (expected ssao, ssm or ssgi)");
}

// Table 1 of the paper (SPEC §3). i = ℓ + 1; the coarsest level covers everything.
namespace {
// By Effect (ssao, ssm, ssgi): the widening's cap, τ_v, the budget B, λ, h and the trim.
struct EffectDefaults {
  int cap;
  float posterior, budget, temporal, hysteresis;
  bool trim;
};
// B = 0.85 (docs/figures.md, "A budget in predicted time and the temporal term"): against B = 0 it
// cut RMS by 18% (SSAO), 11% (SSM) and 69% (SSGI) and flicker on every camera path, measured
// speedups within the loaded VM's noise; --effect-budget 0 is the a-priori method as before. The
// temporal term and the hysteresis stay off: on the bench's paths they raised flicker. The trim
// (SPEC §12.5) is on: on the catalogue it was faster with less error on all three effects
// (docs/figures.md, "The trim"); --effect-trim off is the frame as before, bit for bit.
constexpr EffectDefaults kEffectDefaults[] = {
    {EffectMaskSettings::kDefaultCap, 0.0f, 0.85f, 0.0f, 0.0f, true},  // ssao
    {EffectMaskSettings::kDefaultCap, 0.0f, 0.85f, 0.0f, 0.0f, true},  // ssm
    {EffectMaskSettings::kDefaultCap, 0.0f, 0.85f, 0.0f, 0.0f, true},  // ssgi
};
}  // namespace

Settings defaultSettings(Effect effect) {
  Settings s;
  s.effect = effect;
  switch (effect) {
    case Effect::Ssao:
      s.levels = {{{true, 0.924f, 100.0f}, {true, 1.848f, 50.0f}, {true, 3.696f, 20.0f},
                   {true, 0.0f, 1.0f}}};
      break;
    case Effect::Ssm:
      s.levels = {{{true, 0.924f, 1000.0f}, {true, 1.848f, 1000.0f}, {true, 3.696f, 1000.0f},
                   {true, 0.0f, 1.0f}}};
      break;
    case Effect::Ssgi:  // the paper drops the half level for SSGI
      s.levels = {{{true, 0.924f, 1000.0f}, {false, 0.0f, 0.0f}, {true, 0.924f, 100.0f},
                   {true, 0.0f, 1.0f}}};
      break;
  }
  // mrr-effect's defaults (docs/figures.md, "mrr-effect beyond the catalogue"): the setting that
  // measured best; each is a parameter, so today's earlier settings stay one option away.
  const EffectDefaults& d = kEffectDefaults[static_cast<size_t>(effect)];
  s.effectMask.cap = d.cap;
  s.effectMask.posterior = d.posterior;
  s.effectMask.budget = d.budget;
  s.effectMask.temporal = d.temporal;
  s.effectMask.hysteresis = d.hysteresis;
  s.effectMask.trim = d.trim;
  return s;
}

namespace {
// The sample count of the chosen effect, for Settings and Constants alike.
template <class T>
int samplesOf(const T& t) {
  switch (t.effect) {
    case Effect::Ssm: return t.ssm.samples;
    case Effect::Ssgi: return t.ssgi.samples;
    case Effect::Ssao: break;
  }
  return t.ssao.samples;
}
}  // namespace

int Settings::samples() const { return samplesOf(*this); }

void Settings::setSamples(int n) {
  switch (effect) {
    case Effect::Ssm: ssm.samples = n; return;
    case Effect::Ssgi: ssgi.samples = n; return;
    case Effect::Ssao: ssao.samples = n; return;
  }
}

int Constants::samples() const { return samplesOf(*this); }

namespace {
int squareRoot(int n) {
  int r = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
  return r * r == n ? r : -1;
}
}  // namespace

void validateSettings(const Settings& s) {
  // Every parameter row with a Settings field and a range (common/frame_params.cpp), from its row.
  checkParamRanges(s);
  auto sizeOk = [](int v) { return v >= 1 && v <= kMaxImageSize; };
  // SPEC §13: the gaze inside the frame; the motion term's own knobs (not parameters).
  require(!s.foveation.gaze || (s.foveation.gazeX >= 0 && s.foveation.gazeX < s.width && s.foveation.gazeY >= 0 &&
                                s.foveation.gazeY < s.height),
          optionName(Param::Gaze) + " " + std::to_string(s.foveation.gazeX) + "," + std::to_string(s.foveation.gazeY) +
              ": outside the " + std::to_string(s.width) + "x" + std::to_string(s.height) + " frame (x in [0, " +
              std::to_string(s.width - 1) + "], y in [0, " + std::to_string(s.height - 1) + "])");
  require(s.foveation.motionCap >= 0 && s.foveation.motionCap < kLevelCount,
          "motion cap: must be in [0, " + std::to_string(kLevelCount - 1) + "]");
  require(std::isfinite(s.foveation.motionScale) && s.foveation.motionScale >= 0.0f && s.foveation.motionScale <= 16.0f,
          "motion scale: must be in [0, 16]");
  require(sizeOk(s.width) && sizeOk(s.height),
          optionName(Param::Size) + " " + std::to_string(s.width) + "x" + std::to_string(s.height) +
              ": each side must be in [1, " + std::to_string(kMaxImageSize) + "]");
  require(s.ssao.samples >= 1 && s.ssao.samples <= kMaxSsaoSamples,
          optionName(Param::Samples) + " " + std::to_string(s.ssao.samples) + ": must be in [1, " +
              std::to_string(kMaxSsaoSamples) + "] for ssao");
  require(s.ssm.samples >= 1 && s.ssm.samples <= kMaxSsmSamples && squareRoot(s.ssm.samples) > 0,
          optionName(Param::Samples) + " " + std::to_string(s.ssm.samples) + ": must be a square n*n in [1, " +
              std::to_string(kMaxSsmSamples) + "] for ssm (PCF over an n x n grid, e.g. 196 = 14*14)");
  require(s.ssgi.samples >= 1 && s.ssgi.samples <= kMaxSsgiSamples,
          optionName(Param::Samples) + " " + std::to_string(s.ssgi.samples) + ": must be in [1, " +
              std::to_string(kMaxSsgiSamples) + "] for ssgi");
  require(s.ssm.blockerGrid >= 1 && s.ssm.blockerGrid <= 16, "blocker grid: must be in [1, 16]");
  require(s.ssm.biasTexels >= 0.0f && s.ssm.biasTexels <= 16.0f, "shadow bias: must be in [0, 16] texels");
  require(s.bilateral.radius >= 0 && s.bilateral.radius <= 8, "bilateral radius: must be in [0, 8]");
  require(s.bilateral.sigmaSpatial > 0.0f && s.bilateral.sigmaDepth > 0.0f,
          "bilateral sigmas must be > 0");
  bool any = false;
  for (const LevelSettings& ls : s.levels) any = any || ls.enabled;
  require(s.levels[0].enabled, optionName(Param::DisableLevel) + " 0: the full-resolution level cannot be disabled");
  require(any, "every level is disabled");
}

int Constants::nextCoarserEnabled(int level) const {
  for (int l = level + 1; l < kLevelCount; ++l)
    if (levels[static_cast<size_t>(l)].enabled) return l;
  return -1;
}

void Constants::fallBackToFull() {
  for (LevelConstants& lc : levels) lc.enabled = lc.shaded = lc.index == 0;
  coarsestEnabled = 0;
}

void makeFoveationConstants(const FoveationSettings& s, Constants::Foveation& f) {
  static_cast<FoveationSettings&>(f) = s;
  f.mar0 = kMar0Degrees;
  f.marSlope = kMarSlope;
  for (int l = 0; l < kLevelCount; ++l) {
    // Step 2: level ℓ's pixel, s_ℓ/ppd degrees, at most ω(e)/k: e ≥ e_ℓ = (k s_ℓ/ppd − ω0)/m,
    // r_ℓ = e_ℓ·ppd full-res pixels; d² ≥ ⌈r_ℓ²⌉ ⇔ d ≥ r_ℓ for a whole d² (double on the host).
    const double scale = static_cast<double>(1 << l);
    const double e = (kSamplesPerMar * scale / static_cast<double>(s.ppd) - kMar0Degrees) / kMarSlope;
    const double r = std::max(e, 0.0) * static_cast<double>(s.ppd);
    f.radius2[static_cast<size_t>(l)] = l == 0 ? 0 : static_cast<int64_t>(std::ceil(std::min(r * r, 4.0e18)));
    // Step 4: level ℓ where the box blur of the motion v is at least k level pixels wide: v ≥ k s_ℓ.
    f.speed2[static_cast<size_t>(l)] = l == 0 ? 0.0f : static_cast<float>((kSamplesPerMar * scale) * (kSamplesPerMar * scale));
  }
}

Constants makeConstants(const Settings& s, float framedSize) {
  validateSettings(s);
  Constants c;
  c.width = s.width;
  c.height = s.height;
  c.effect = s.effect;
  c.mode = s.mode;
  // SPEC §0: pad to a multiple of the coarsest scale so every level grid nests exactly.
  const int coarsestScale = 1 << (kLevelCount - 1);
  c.paddedWidth = (s.width + coarsestScale - 1) / coarsestScale * coarsestScale;
  c.paddedHeight = (s.height + coarsestScale - 1) / coarsestScale * coarsestScale;
  for (int l = 0; l < kLevelCount; ++l) {
    LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const LevelSettings& ls = s.levels[static_cast<size_t>(l)];
    lc.index = l;
    lc.scale = 1 << l;
    lc.width = c.paddedWidth / lc.scale;
    lc.height = c.paddedHeight / lc.scale;
    // The method's levels (common/methods.h): the user's (--disable-level) or its own.
    const MethodInfo& m = methodInfo(s.mode);
    lc.enabled = m.userLevels ? ls.enabled : (m.levels >> l & 1u) != 0;
    lc.shaded = (m.shades >> l & 1u) != 0;
    lc.shaded = lc.shaded && lc.enabled;
    lc.sigma2 = ls.sigma2;
    lc.weight = ls.weight;
    lc.blurRadius = gaussianRadius(ls.sigma2);
    lc.gaussian = gaussianWeights(ls.sigma2);
  }
  c.finestEnabled = 0;
  c.coarsestEnabled = 0;
  for (int l = 0; l < kLevelCount; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled) c.coarsestEnabled = l;
  c.edges = s.edges;
  c.neverSlower = s.neverSlower && methodInfo(s.mode).neverSlower;
  c.effectMask = s.effectMask;
  // SPEC §14: the temporal term of the frame's method (mrr-effect's, or tiles' for comparison).
  c.temporal.lambda = s.mode == Mode::MrrEffect ? s.effectMask.temporal : s.mode == Mode::Tiles ? s.tilesTemporal : 0.0f;
  c.temporal.depthTolerance = kTemporalDepthTolerance;
  c.temporal.normalCos = kTemporalNormalCos;
  makeFoveationConstants(s.foveation, c.foveation);

  c.renderCoarseGBuffer = s.renderCoarseGBuffer;
  c.ssao.samples = s.ssao.samples;
  c.ssao.radius = s.ssao.radius > 0.0f
                      ? s.ssao.radius
                      : SsaoSettings::kAutoRadiusFraction * std::max(framedSize, 1e-6f);
  c.ssao.bias = s.ssao.biasFraction * c.ssao.radius;
  c.ssao.tangentPlaneDepth = s.ssao.tangentPlaneDepth;
  c.ssao.kernel = ssaoKernel(s.ssao.samples, kernelSeed(kSsaoKernelSeed, s.seed));
  c.ssao.seed = s.seed;

  c.ssm.samples = s.ssm.samples;
  c.ssm.grid = squareRoot(s.ssm.samples);
  c.ssm.shadowMapSize = s.ssm.shadowMapSize;
  c.ssm.tanHalfAngle = std::tan(0.5f * s.ssm.lightAngle);
  c.ssm.blockerGrid = s.ssm.blockerGrid;
  c.ssm.biasTexels = s.ssm.biasTexels;

  c.ssgi.samples = s.ssgi.samples;
  c.ssgi.radius = s.ssgi.radius > 0.0f ? s.ssgi.radius
                                       : SsgiSettings::kAutoRadiusFraction * std::max(framedSize, 1e-6f);
  c.ssgi.patchArea = 3.14159265f * c.ssgi.radius * c.ssgi.radius / static_cast<float>(s.ssgi.samples);
  c.ssgi.minDistance2 = 0.0625f * c.ssgi.radius * c.ssgi.radius;
  c.ssgi.kernel = ssaoKernel(s.ssgi.samples, kernelSeed(kSsgiKernelSeed, s.seed));
  c.ssgi.seed = s.seed;

  c.bilateral.radius = s.bilateral.radius;
  c.bilateral.sigmaDepth = s.bilateral.sigmaDepth;
  c.bilateral.normalPower = s.bilateral.normalPower;
  const int r = s.bilateral.radius;
  const double twoSigma2 = 2.0 * s.bilateral.sigmaSpatial * s.bilateral.sigmaSpatial;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx)
      c.bilateral.spatial.push_back(static_cast<float>(std::exp(-(dx * dx + dy * dy) / twoSigma2)));
  return c;
}

}  // namespace mrr
