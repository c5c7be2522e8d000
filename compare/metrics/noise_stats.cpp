#include "compare/metrics/noise_stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/error.h"

namespace mrr {

namespace {

// The continued fraction of the regularised incomplete beta function (modified Lentz), valid
// for x < (a + 1) / (a + b + 2).
double betaContinuedFraction(double a, double b, double x) {
  constexpr double kTiny = 1e-300, kEps = 1e-15;
  double c = 1.0, d = 1.0 - (a + b) * x / (a + 1.0);
  if (std::fabs(d) < kTiny) d = kTiny;
  d = 1.0 / d;
  double h = d;
  for (int m = 1; m <= 1000; ++m) {
    const double m2 = 2.0 * m;
    double aa = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    h *= d * c;
    aa = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0));
    d = 1.0 + aa * d;
    if (std::fabs(d) < kTiny) d = kTiny;
    c = 1.0 + aa / c;
    if (std::fabs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double step = d * c;
    h *= step;
    if (std::fabs(step - 1.0) < kEps) break;
  }
  return h;
}

// I_x(a, b), the regularised incomplete beta function.
double incompleteBeta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  const double front =
      std::exp(std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x));
  if (x < (a + 1.0) / (a + b + 2.0)) return front * betaContinuedFraction(a, b, x) / a;
  return 1.0 - front * betaContinuedFraction(b, a, 1.0 - x) / b;
}

}  // namespace

double studentTTwoSided(double t, double df) {
  require(df > 0.0, "internal: Student's t needs df > 0");
  if (std::isnan(t)) return std::numeric_limits<double>::quiet_NaN();
  if (std::isinf(t)) return 0.0;
  // P(|T| ≥ |t|) = I_{ν/(ν+t²)}(ν/2, 1/2)
  return incompleteBeta(0.5 * df, 0.5, df / (df + t * t));
}

double studentTCdf(double t, double df) {
  const double tail = 0.5 * studentTTwoSided(t, df);
  return t >= 0.0 ? 1.0 - tail : tail;
}

double studentTCritical(double p, double df) {
  require(p > 0.0 && p <= 1.0, "internal: a two-sided p must be in (0, 1]");
  // P(|T| ≥ t) falls monotonically in t: bisect (on a log scale past 1).
  double lo = 0.0, hi = 1.0;
  while (studentTTwoSided(hi, df) > p) {
    lo = hi;
    hi *= 2.0;
    if (hi > 1e12) return hi;
  }
  for (int i = 0; i < 200 && hi - lo > 1e-12 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (studentTTwoSided(mid, df) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double sidakLevel(double alpha, int64_t tests) {
  require(alpha > 0.0 && alpha < 1.0, "internal: a significance level must be in (0, 1)");
  if (tests <= 1) return alpha;
  // 1 − (1 − α)^(1/m) = −expm1(log1p(−α) / m)
  return -std::expm1(std::log1p(-alpha) / static_cast<double>(tests));
}

WelchResult welchTest(double meanA, double varMeanA, double dfA, double meanB, double varMeanB, double dfB) {
  WelchResult r;
  const double v = varMeanA + varMeanB;
  const double d = meanA - meanB;
  if (!(v > 0.0)) {  // no spread at all: equal means pass, others are infinitely far
    r.t = d == 0.0 ? 0.0 : std::copysign(std::numeric_limits<double>::infinity(), d);
    r.df = std::max(dfA, dfB);
    r.p = d == 0.0 ? 1.0 : 0.0;
    return r;
  }
  r.t = d / std::sqrt(v);
  // Welch–Satterthwaite
  const double denominator = (dfA > 0.0 ? varMeanA * varMeanA / dfA : 0.0) + (dfB > 0.0 ? varMeanB * varMeanB / dfB : 0.0);
  r.df = denominator > 0.0 ? v * v / denominator : std::max(dfA, dfB);
  r.df = std::max(r.df, 1.0);
  r.p = studentTTwoSided(r.t, r.df);
  return r;
}

MeanInterval meanInterval(const std::vector<double>& values, double confidence) {
  require(values.size() >= 2, "internal: an interval needs two values");
  MeanInterval m;
  const double n = static_cast<double>(values.size());
  for (double v : values) m.mean += v;
  m.mean /= n;
  double ss = 0.0;
  for (double v : values) ss += (v - m.mean) * (v - m.mean);
  m.sd = std::sqrt(ss / (n - 1.0));
  const double half = studentTCritical(1.0 - confidence, n - 1.0) * m.sd / std::sqrt(n);
  m.lo = m.mean - half;
  m.hi = m.mean + half;
  return m;
}

bool NoiseFigures::pass() const {
  return rejected == 0 && std::all_of(biases.begin(), biases.end(), [](const RegionBias& b) { return b.pass; });
}

std::string NoiseFigures::describe() const {
  char text[256];
  std::snprintf(text, sizeof text, "%.3g%% of %lld px rejected (K = %d seeds, Sidak level %.2g per test)",
                100.0 * shareRejected, static_cast<long long>(pixels), seeds, pixelLevel);
  std::string out = text;
  for (const RegionBias& b : biases) {
    const double k = b.relative ? 100.0 : 1.0;
    const char* unit = b.relative ? "%" : "";
    std::snprintf(text, sizeof text, "; bias %+.3g%s [%+.3g%s, %+.3g%s] over %s%s", k * b.bias, unit, k * b.lo, unit,
                  k * b.hi, unit, b.region.c_str(), b.pass ? "" : " (!)");
    out += text;
  }
  if (worstX >= 0) {
    std::snprintf(text, sizeof text,
                  "; worst pixel %d,%d (full res): %.4g against the oracle's mean %.4g, accepted in [%.4g, %.4g], t = %.3g%s",
                  worstX * scale + scale / 2, worstY * scale + scale / 2, worstValue, worstMean, worstLo, worstHi, worstT,
                  worstP < pixelLevel ? " (!)" : "");
    out += text;
  }
  return out;
}

}  // namespace mrr
