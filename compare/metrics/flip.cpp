#include "compare/metrics/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "common/error.h"

namespace mrr {
namespace {

using Mat3 = std::array<float, 9>;  // row-major

// Linear sRGB (ITU-R BT.709 primaries) to CIE XYZ, D65 (IEC 61966-2-1).
constexpr double kRgbToXyz[9] = {0.4124564, 0.3575761, 0.1804375,  //
                                 0.2126729, 0.7151522, 0.0721750,  //
                                 0.0193339, 0.1191920, 0.9503041};

// The colour-space constants, computed once in double. The reference white is the XYZ of
// RGB (1,1,1), D65 as the matrix holds it, so that white has Cx = Cz = a* = b* = 0 exactly.
struct ColourSpace {
  Mat3 rgbToRel;  // linear RGB → XYZ / white
  Mat3 relToRgb;  // XYZ / white → linear RGB
  ColourSpace() {
    double white[3], m[9], inv[9];
    for (int r = 0; r < 3; ++r) white[r] = kRgbToXyz[3 * r] + kRgbToXyz[3 * r + 1] + kRgbToXyz[3 * r + 2];
    for (int i = 0; i < 9; ++i) m[i] = kRgbToXyz[i] / white[i / 3];
    const double det = m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
                       m[2] * (m[3] * m[7] - m[4] * m[6]);
    inv[0] = (m[4] * m[8] - m[5] * m[7]) / det;
    inv[1] = (m[2] * m[7] - m[1] * m[8]) / det;
    inv[2] = (m[1] * m[5] - m[2] * m[4]) / det;
    inv[3] = (m[5] * m[6] - m[3] * m[8]) / det;
    inv[4] = (m[0] * m[8] - m[2] * m[6]) / det;
    inv[5] = (m[2] * m[3] - m[0] * m[5]) / det;
    inv[6] = (m[3] * m[7] - m[4] * m[6]) / det;
    inv[7] = (m[1] * m[6] - m[0] * m[7]) / det;
    inv[8] = (m[0] * m[4] - m[1] * m[3]) / det;
    for (int i = 0; i < 9; ++i) {
      rgbToRel[static_cast<size_t>(i)] = static_cast<float>(m[i]);
      relToRgb[static_cast<size_t>(i)] = static_cast<float>(inv[i]);
    }
  }
};
const ColourSpace& colourSpace() {
  static const ColourSpace cs;
  return cs;
}

inline float srgbDecode(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

// CIELAB's f(t): a cube root above (6/29)³, a line below.
inline float labF(float t) {
  constexpr float kDelta = 6.0f / 29.0f;
  constexpr float kDelta3 = kDelta * kDelta * kDelta;
  constexpr float kSlope = 1.0f / (3.0f * kDelta * kDelta);
  return t > kDelta3 ? std::cbrt(t) : kSlope * t + 4.0f / 29.0f;
}

// Linear RGB in [0,1] → CIELAB with the Hunt adjustment (chroma scaled by 0.01·L*): the
// space where the paper measures colour differences.
struct HuntLab {
  float l, a, b;
};
inline HuntLab huntLab(float r, float g, float b, const Mat3& m) {
  const float fx = labF(m[0] * r + m[1] * g + m[2] * b);
  const float fy = labF(m[3] * r + m[4] * g + m[5] * b);
  const float fz = labF(m[6] * r + m[7] * g + m[8] * b);
  const float l = 116.0f * fy - 16.0f;
  return {l, 0.01f * l * 500.0f * (fx - fy), 0.01f * l * 200.0f * (fy - fz)};
}

// HyAB: city-block distance in lightness, Euclidean in chroma.
inline float hyab(const HuntLab& p, const HuntLab& q) {
  const float da = p.a - q.a, db = p.b - q.b;
  return std::abs(p.l - q.l) + std::sqrt(da * da + db * db);
}

// One separable component: 2r+1 taps, the k-th at offset k − r.
struct Taps {
  int radius = 0;
  std::vector<float> w;
};

// The contrast-sensitivity filters of the three opponent channels. Each channel's 2D filter
// is Σ_i a_i·sqrt(π/b_i)·exp(−π²(x²+y²)/b_i) over a square window, normalised to sum 1. Each
// term is separable (a 1D Gaussian in x times one in y), so the 2D filter is the sum of at
// most two separable filters; a component's 1D taps carry the square root of its share of
// the normalisation, so that its x and y passes together apply it once.
struct CsfFilters {
  int radius = 0;
  std::vector<Taps> components;  // Y, Cx, then Cz's one or two
  int firstOf[3] = {0, 0, 0}, countOf[3] = {0, 0, 0};
};

CsfFilters makeCsfFilters(double ppd, const FlipConstants& k) {
  constexpr double kPi = std::numbers::pi;
  double bMax = 0.0;
  for (int c = 0; c < 3; ++c) bMax = std::max({bMax, k.b1[c], k.a2[c] != 0.0 ? k.b2[c] : 0.0});
  // Three standard deviations of the widest Gaussian (σ = sqrt(b / 2π²) degrees) in pixels.
  CsfFilters f;
  f.radius = static_cast<int>(std::ceil(3.0 * std::sqrt(bMax / (2.0 * kPi * kPi)) * ppd));
  const int n = 2 * f.radius + 1;
  for (int c = 0; c < 3; ++c) {
    std::vector<std::vector<double>> gaussians;
    std::vector<double> weights, sums;
    double total = 0.0;
    for (int i = 0; i < 2; ++i) {
      const double a = i == 0 ? k.a1[c] : k.a2[c], b = i == 0 ? k.b1[c] : k.b2[c];
      if (a == 0.0) continue;
      std::vector<double> g(static_cast<size_t>(n));
      double sum = 0.0;
      for (int x = 0; x < n; ++x) {
        const double degrees = (x - f.radius) / ppd;
        g[static_cast<size_t>(x)] = std::exp(-kPi * kPi * degrees * degrees / b);
        sum += g[static_cast<size_t>(x)];
      }
      const double weight = a * std::sqrt(kPi / b);
      total += weight * sum * sum;  // the 2D term's sum: weight · (Σ_x g)(Σ_y g)
      gaussians.push_back(std::move(g));
      weights.push_back(weight);
    }
    f.firstOf[c] = static_cast<int>(f.components.size());
    f.countOf[c] = static_cast<int>(gaussians.size());
    for (size_t i = 0; i < gaussians.size(); ++i) {
      const double scale = std::sqrt(weights[i] / total);
      Taps t{f.radius, std::vector<float>(static_cast<size_t>(n))};
      for (int x = 0; x < n; ++x) t.w[static_cast<size_t>(x)] = static_cast<float>(scale * gaussians[i][static_cast<size_t>(x)]);
      f.components.push_back(std::move(t));
    }
  }
  return f;
}

// The feature filters: a Gaussian of σ = w/2·ppd pixels and its first and second
// derivatives, over three σ. The Gaussian sums to 1; each derivative's positive taps sum
// to 1 and its negative taps to −1, so that a unit step or a unit line gives a unit response.
struct FeatureFilters {
  Taps g, dg, ddg;
};

FeatureFilters makeFeatureFilters(double ppd, const FlipConstants& k) {
  const double sigma = 0.5 * k.w * ppd;
  const int r = static_cast<int>(std::ceil(3.0 * sigma));
  const int n = 2 * r + 1;
  std::vector<double> g(static_cast<size_t>(n)), dg(g.size()), ddg(g.size());
  double gSum = 0.0, dgPos = 0.0, dgNeg = 0.0, ddgPos = 0.0, ddgNeg = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = i - r;
    const size_t s = static_cast<size_t>(i);
    g[s] = std::exp(-x * x / (2.0 * sigma * sigma));
    dg[s] = -x * g[s];                                  // ∝ d/dx
    ddg[s] = (x * x / (sigma * sigma) - 1.0) * g[s];   // ∝ d²/dx²
    gSum += g[s];
    (dg[s] > 0.0 ? dgPos : dgNeg) += std::abs(dg[s]);
    (ddg[s] > 0.0 ? ddgPos : ddgNeg) += std::abs(ddg[s]);
  }
  FeatureFilters f{{r, std::vector<float>(g.size())}, {r, std::vector<float>(g.size())}, {r, std::vector<float>(g.size())}};
  for (size_t s = 0; s < g.size(); ++s) {
    f.g.w[s] = static_cast<float>(g[s] / gSum);
    f.dg.w[s] = static_cast<float>(dg[s] / (dg[s] > 0.0 ? dgPos : dgNeg));
    f.ddg.w[s] = static_cast<float>(ddg[s] / (ddg[s] > 0.0 ? ddgPos : ddgNeg));
  }
  return f;
}

// out[x] = Σ_k w[k]·row[clamp(x + k − r)]: `padded` holds the row with r clamped copies of
// its end pixels on each side. Loops run over x innermost, so they vectorise; every pixel
// sums its taps in the same order.
void convolveRow(const float* padded, int width, const Taps& t, float* out) {
  std::fill(out, out + width, 0.0f);
  for (size_t k = 0; k < t.w.size(); ++k) {
    const float w = t.w[k];
    const float* src = padded + k;
    for (int x = 0; x < width; ++x) out[x] += w * src[x];
  }
}

// out[x] = Σ_k w[k]·plane[clamp(y + k − r)][x].
void convolveColumn(const float* plane, int width, int height, int y, const Taps& t, float* out) {
  std::fill(out, out + width, 0.0f);
  for (size_t k = 0; k < t.w.size(); ++k) {
    const float w = t.w[k];
    const int yy = std::clamp(y + static_cast<int>(k) - t.radius, 0, height - 1);
    const float* src = plane + static_cast<size_t>(yy) * width;
    for (int x = 0; x < width; ++x) out[x] += w * src[x];
  }
}

void fillPadded(const float* row, int width, int radius, float* padded) {
  for (int i = 0; i < radius; ++i) padded[i] = row[0];
  std::copy(row, row + width, padded + radius);
  for (int i = 0; i < radius; ++i) padded[radius + width + i] = row[width - 1];
}

// A W×H plane of floats whose every pixel the pipeline writes.
using Plane = PixelVector<float>;

// The per-image planes after the horizontal passes: the CSF components and the feature
// filters (Gaussian, first and second derivative) of the achromatic channel.
struct Horizontal {
  std::vector<Plane> csf;  // one per CSF component
  Plane g, dg, ddg;
};

// Step 1, one row of one image: sRGB display values → linear RGB → YyCxCz (the paper's
// opponent space: Yy = 116·Y/Yn − 16, Cx = 500·(X/Xn − Y/Yn), Cz = 200·(Y/Yn − Z/Zn)).
void opponentRow(const ImageF& image, int y, const Mat3& m, float* yy, float* cx, float* cz) {
  const int ch = image.channels;
  for (int x = 0; x < image.width; ++x) {
    const float* p = &image.data[image.index(x, y)];
    float r, g, b;
    if (ch >= 3) {
      r = srgbDecode(std::clamp(p[0], 0.0f, 1.0f));
      g = srgbDecode(std::clamp(p[1], 0.0f, 1.0f));
      b = srgbDecode(std::clamp(p[2], 0.0f, 1.0f));
    } else {  // grey (a second channel is alpha)
      r = g = b = srgbDecode(std::clamp(p[0], 0.0f, 1.0f));
    }
    if (std::isnan(r)) r = 0.0f;  // clamp lets NaN through
    if (std::isnan(g)) g = 0.0f;
    if (std::isnan(b)) b = 0.0f;
    const float xr = m[0] * r + m[1] * g + m[2] * b;
    const float yr = m[3] * r + m[4] * g + m[5] * b;
    const float zr = m[6] * r + m[7] * g + m[8] * b;
    yy[x] = 116.0f * yr - 16.0f;
    cx[x] = 500.0f * (xr - yr);
    cz[x] = 200.0f * (yr - zr);
  }
}

Horizontal horizontalPasses(const ImageF& image, const CsfFilters& csf, const FeatureFilters& feat) {
  const int w = image.width, h = image.height;
  const size_t n = image.pixelCount();
  Horizontal out;
  out.csf.resize(csf.components.size());
  for (Plane& p : out.csf) p.resize(n);
  out.g.resize(n);
  out.dg.resize(n);
  out.ddg.resize(n);
  const Mat3& m = colourSpace().rgbToRel;
  const int pad = std::max(csf.radius, feat.g.radius);
  parallelFor(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
    std::vector<float> opp[3], padded(static_cast<size_t>(w + 2 * pad)), grey(static_cast<size_t>(w));
    for (auto& o : opp) o.resize(static_cast<size_t>(w));
    for (int y = rows.begin(); y != rows.end(); ++y) {
      const size_t row = static_cast<size_t>(y) * w;
      opponentRow(image, y, m, opp[0].data(), opp[1].data(), opp[2].data());
      for (int c = 0; c < 3; ++c) {
        fillPadded(opp[c].data(), w, csf.radius, padded.data());
        for (int i = 0; i < csf.countOf[c]; ++i) {
          const size_t comp = static_cast<size_t>(csf.firstOf[c] + i);
          convolveRow(padded.data(), w, csf.components[comp], &out.csf[comp][row]);
        }
      }
      // Features see the achromatic channel as grey in [0,1]: (Yy + 16) / 116 = Y / Yn.
      for (int x = 0; x < w; ++x) grey[static_cast<size_t>(x)] = (opp[0][static_cast<size_t>(x)] + 16.0f) / 116.0f;
      fillPadded(grey.data(), w, feat.g.radius, padded.data());
      convolveRow(padded.data(), w, feat.g, &out.g[row]);
      convolveRow(padded.data(), w, feat.dg, &out.dg[row]);
      convolveRow(padded.data(), w, feat.ddg, &out.ddg[row]);
    }
  });
  return out;
}

// The colour error's remapping (paper: errors up to pc·cmax map linearly to [0, pt], the
// rest to (pt, 1]), with cmax the compressed HyAB distance of green to blue, the largest of
// any pair of primaries.
struct ColourRemap {
  float cmax, pccmax, pt;
  explicit ColourRemap(const FlipConstants& k, const Mat3& m) {
    const HuntLab green = huntLab(0.0f, 1.0f, 0.0f, m), blue = huntLab(0.0f, 0.0f, 1.0f, m);
    cmax = std::pow(hyab(green, blue), static_cast<float>(k.qc));
    pccmax = static_cast<float>(k.pc) * cmax;
    pt = static_cast<float>(k.pt);
  }
  float operator()(float compressed) const {
    return compressed < pccmax ? compressed * (pt / pccmax)
                               : pt + (compressed - pccmax) / (cmax - pccmax) * (1.0f - pt);
  }
};

}  // namespace

FlipResult flip(const ImageF& reference, const ImageF& test, double ppd) {
  require(reference.width == test.width && reference.height == test.height,
          "the images differ in size: " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
              " against " + std::to_string(test.width) + "x" + std::to_string(test.height));
  require(reference.channels >= 1 && test.channels >= 1 && !reference.empty(), "FLIP needs two non-empty images");
  require(std::isfinite(ppd) && ppd > 0.0 && ppd <= 1000.0, "--ppd: must be in (0, 1000]");
  const FlipConstants k;
  const CsfFilters csf = makeCsfFilters(ppd, k);
  const FeatureFilters feat = makeFeatureFilters(ppd, k);
  const int w = reference.width, h = reference.height;

  // 1–2. Opponent space, then the horizontal halves of the CSF and feature filters.
  const Horizontal ref = horizontalPasses(reference, csf, feat);
  const Horizontal tst = horizontalPasses(test, csf, feat);

  // 3. The vertical halves, then per pixel: the colour error, the feature error, the FLIP.
  const ColourSpace& cs = colourSpace();
  const ColourRemap remap(k, cs.rgbToRel);
  const float qc = static_cast<float>(k.qc), qf = static_cast<float>(k.qf);
  const float featureScale = 1.0f / std::sqrt(2.0f);
  FlipResult result;
  result.errorMap = ImageF::uninitialised(w, h, 1);
  parallelFor(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
    const size_t W = static_cast<size_t>(w);
    // Filtered opponent channels of both images; the feature responses.
    std::vector<float> opp[2][3], part(W), feature[2][4];
    for (auto& side : opp)
      for (auto& o : side) o.resize(W);
    for (auto& side : feature)
      for (auto& f : side) f.resize(W);
    for (int y = rows.begin(); y != rows.end(); ++y) {
      for (int s = 0; s < 2; ++s) {
        const Horizontal& hp = s == 0 ? ref : tst;
        for (int c = 0; c < 3; ++c) {
          for (int i = 0; i < csf.countOf[c]; ++i) {
            const size_t comp = static_cast<size_t>(csf.firstOf[c] + i);
            float* dst = i == 0 ? opp[s][c].data() : part.data();
            convolveColumn(hp.csf[comp].data(), w, h, y, csf.components[comp], dst);
            if (i > 0)
              for (size_t x = 0; x < W; ++x) opp[s][c][x] += part[x];
          }
        }
        // ∂/∂x: derivative across the row, Gaussian down the column; ∂/∂y the other way.
        convolveColumn(hp.dg.data(), w, h, y, feat.g, feature[s][0].data());   // edge, x
        convolveColumn(hp.g.data(), w, h, y, feat.dg, feature[s][1].data());   // edge, y
        convolveColumn(hp.ddg.data(), w, h, y, feat.g, feature[s][2].data());  // point, x
        convolveColumn(hp.g.data(), w, h, y, feat.ddg, feature[s][3].data());  // point, y
      }
      float* out = &result.errorMap.data[static_cast<size_t>(y) * W];
      for (size_t x = 0; x < W; ++x) {
        HuntLab lab[2];
        float edge[2], point[2];
        for (int s = 0; s < 2; ++s) {
          // Filtered YyCxCz → XYZ / white → linear RGB, clamped to the displayable [0,1].
          const float yr = (opp[s][0][x] + 16.0f) / 116.0f;
          const float xr = yr + opp[s][1][x] / 500.0f;
          const float zr = yr - opp[s][2][x] / 200.0f;
          const Mat3& mi = cs.relToRgb;
          const float r = std::clamp(mi[0] * xr + mi[1] * yr + mi[2] * zr, 0.0f, 1.0f);
          const float g = std::clamp(mi[3] * xr + mi[4] * yr + mi[5] * zr, 0.0f, 1.0f);
          const float b = std::clamp(mi[6] * xr + mi[7] * yr + mi[8] * zr, 0.0f, 1.0f);
          lab[s] = huntLab(r, g, b, cs.rgbToRel);
          edge[s] = std::sqrt(feature[s][0][x] * feature[s][0][x] + feature[s][1][x] * feature[s][1][x]);
          point[s] = std::sqrt(feature[s][2][x] * feature[s][2][x] + feature[s][3][x] * feature[s][3][x]);
        }
        const float colour = remap(std::pow(hyab(lab[0], lab[1]), qc));
        const float featureError = std::pow(
            featureScale * std::max(std::abs(edge[0] - edge[1]), std::abs(point[0] - point[1])), qf);
        out[x] = std::pow(colour, 1.0f - featureError);
      }
    }
  });
  result.stats = flipStats(result.errorMap);
  return result;
}

namespace {
// The p-quantile of `values` (linear between order statistics); reorders `values`.
double quantile(std::vector<float>& values, double p) {
  const double position = p * static_cast<double>(values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(position));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(lo), values.end());
  const double low = values[lo];
  if (lo + 1 >= values.size()) return low;
  const double high = *std::min_element(values.begin() + static_cast<std::ptrdiff_t>(lo) + 1, values.end());
  return low + (position - static_cast<double>(lo)) * (high - low);
}
}  // namespace

FlipStats flipStats(const ImageF& errorMap) {
  FlipStats s;
  if (errorMap.empty()) return s;
  const size_t n = errorMap.data.size();
  // Rows summed in double, then the rows in order: the same figure for any thread count.
  const int h = errorMap.height;
  const size_t rowLength = n / static_cast<size_t>(h);
  std::vector<double> rowSums(static_cast<size_t>(h));
  std::vector<float> rowMax(static_cast<size_t>(h));
  parallelFor(0, h, [&](int y) {
    double sum = 0.0;
    float mx = 0.0f;
    for (size_t i = static_cast<size_t>(y) * rowLength, end = i + rowLength; i < end; ++i) {
      sum += errorMap.data[i];
      mx = std::max(mx, errorMap.data[i]);
    }
    rowSums[static_cast<size_t>(y)] = sum;
    rowMax[static_cast<size_t>(y)] = mx;
  });
  double sum = 0.0;
  for (double r : rowSums) sum += r;
  s.mean = sum / static_cast<double>(n);
  s.max = *std::max_element(rowMax.begin(), rowMax.end());
  std::vector<float> values(errorMap.data.begin(), errorMap.data.end());
  s.q1 = quantile(values, 0.25);
  s.median = quantile(values, 0.5);
  s.q3 = quantile(values, 0.75);
  return s;
}

ImageF linearToDisplay(const ImageF& linear) {
  ImageF out = ImageF::uninitialised(linear.width, linear.height, linear.channels);
  parallelFor(size_t{0}, linear.data.size(), [&](size_t i) {
    const float v = linear.data[i];
    const double c = std::isnan(v) ? 0.0 : std::clamp(static_cast<double>(v), 0.0, 1.0);
    // The sRGB OETF, as --shaded writes its PNG (common/image_io.cpp).
    out.data[i] = static_cast<float>(c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055);
  });
  return out;
}

namespace {
constexpr unsigned char kMagma[256][3] = {
#include "compare/metrics/flip_magma.inc"
};

void magma(float v, float* rgb) {
  const float c = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
  const unsigned char* m = kMagma[static_cast<int>(std::lround(c * 255.0f))];
  for (int i = 0; i < 3; ++i) rgb[i] = static_cast<float>(m[i]) / 255.0f;
}
}  // namespace

void flipMagma(float v, uint8_t* rgb) {
  const float c = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
  const unsigned char* m = kMagma[static_cast<int>(std::lround(c * 255.0f))];
  for (int i = 0; i < 3; ++i) rgb[i] = m[i];
}

std::string flipMagmaGradient() {
  std::string css = "linear-gradient(to right";
  for (int i = 0; i <= 255; i += 17)  // 16 stops, 0 to 255
    css += ",rgb(" + std::to_string(kMagma[i][0]) + "," + std::to_string(kMagma[i][1]) + "," + std::to_string(kMagma[i][2]) + ")";
  return css + ")";
}

ImageU8 flipColourMapBytes(const ImageF& errorMap) {
  ImageU8 out(errorMap.width, errorMap.height, 3, 0);
  parallelFor(0, errorMap.height, [&](int y) {
    for (int x = 0; x < errorMap.width; ++x) flipMagma(errorMap.at(x, y, 0), &out.at(x, y, 0));
  });
  return out;
}

ImageF flipColourMap(const ImageF& errorMap, bool legend) {
  const int w = errorMap.width, h = errorMap.height;
  // The colour bar: a gap, then the scale, with ticks at each 0.1 (longer at 0, 0.5 and 1).
  const int gap = legend ? std::max(2, h / 100) : 0;
  const int bar = legend ? std::clamp(h / 16, 8, 48) : 0;
  ImageF out(w, h + gap + bar, 3, 0.0f);
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) magma(errorMap.at(x, y, 0), &out.at(x, y, 0));
  });
  if (legend) {
    for (int x = 0; x < w; ++x) {
      const float v = w > 1 ? static_cast<float>(x) / static_cast<float>(w - 1) : 0.0f;
      const int tenth = static_cast<int>(std::lround(v * 10.0f));
      const int tickX = w > 1 ? static_cast<int>(std::lround(tenth / 10.0 * (w - 1))) : 0;
      const bool major = tenth % 5 == 0;
      const int tick = x == tickX ? (major ? bar / 2 : bar / 4) : 0;
      for (int y = 0; y < bar; ++y) {
        float* p = &out.at(x, h + gap + y, 0);
        magma(v, p);
        if (y < tick) p[0] = p[1] = p[2] = v < 0.5f ? 1.0f : 0.0f;  // white on dark, black on light
      }
    }
  }
  return out;
}

}  // namespace mrr
