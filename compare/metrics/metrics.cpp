#include "compare/metrics/metrics.h"

#include <tbb/blocked_range.h>
#include "common/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "compare/metrics/flip.h"

namespace mrr {

namespace {

std::string sizeText(const ImageF& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height) + "x" +
         std::to_string(image.channels);
}

void requireComparable(const ImageF& test, const ImageF& ref, const char* what) {
  require(test.width == ref.width && test.height == ref.height && test.channels == ref.channels,
          std::string(what) + ": image sizes differ (" + sizeText(test) + " vs reference " +
              sizeText(ref) + ")");
  require(test.width > 0 && test.height > 0 && test.channels > 0,
          std::string(what) + ": empty image");
  require(test.data.size() == test.pixelCount() * static_cast<size_t>(test.channels) &&
              ref.data.size() == test.data.size(),
          std::string(what) + ": image data size does not match its dimensions");
}

// Runs rowValue(y) for every row in parallel and sums the per-row doubles in row order,
// so the result does not depend on the thread count or the scheduling.
template <class RowValue>
double sumRows(int rows, RowValue&& rowValue) {
  std::vector<double> partial(static_cast<size_t>(rows), 0.0);
  parallelFor(tbb::blocked_range<int>(0, rows), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) partial[static_cast<size_t>(y)] = rowValue(y);
  });
  double total = 0.0;
  for (double value : partial) total += value;
  return total;
}

double meanSquaredError(const ImageF& test, const ImageF& ref) {
  const size_t rowLength = static_cast<size_t>(test.width) * test.channels;
  const double sum = sumRows(test.height, [&](int y) {
    const size_t begin = static_cast<size_t>(y) * rowLength;
    double rowSum = 0.0;
    for (size_t i = begin; i < begin + rowLength; ++i) {
      const double d = static_cast<double>(test.data[i]) - static_cast<double>(ref.data[i]);
      rowSum += d * d;
    }
    return rowSum;
  });
  return sum / static_cast<double>(test.data.size());
}

// SSIM window (Wang et al. 2004): 11 taps of a Gaussian with σ = 1.5, normalised, as
// scipy.ndimage builds it for skimage (radius int(3.5·σ + 0.5) = 5).
constexpr int kSsimRadius = 5;
constexpr int kSsimTaps = 2 * kSsimRadius + 1;
constexpr double kSsimSigma = 1.5;
constexpr double kSsimC1 = 0.01 * 0.01;  // (K1·L)², L = 1
constexpr double kSsimC2 = 0.03 * 0.03;  // (K2·L)²

std::array<double, kSsimTaps> gaussianTaps() {
  std::array<double, kSsimTaps> taps{};
  double sum = 0.0;
  for (int i = 0; i < kSsimTaps; ++i) {
    const double x = static_cast<double>(i - kSsimRadius);
    taps[static_cast<size_t>(i)] = std::exp(-0.5 / (kSsimSigma * kSsimSigma) * x * x);
    sum += taps[static_cast<size_t>(i)];
  }
  for (double& t : taps) t /= sum;
  return taps;
}

// One axis of the SSIM window: which output positions are evaluated and, for each, the
// first input sample and the weights. An axis of at least 11 samples uses the "valid"
// positions only (the window lies fully inside, as skimage's crop by (11-1)/2 does). A
// shorter axis cannot hold one full window, so every position is evaluated with the window
// clipped to the image and its weights renormalised; this keeps tiny images (down to 1×1)
// well defined instead of failing.
struct WindowAxis {
  int outputs = 0;
  bool full = false;            // every window has all 11 taps and first[o] == o
  std::vector<int> first;       // first input index per output
  std::vector<int> count;       // taps per output
  std::vector<double> weights;  // outputs × kSsimTaps, row o holds count[o] weights

  double weight(int o, int k) const {
    return weights[static_cast<size_t>(o) * kSsimTaps + static_cast<size_t>(k)];
  }
};

WindowAxis windowAxis(int length) {
  static const std::array<double, kSsimTaps> kTaps = gaussianTaps();
  WindowAxis axis;
  axis.full = length >= kSsimTaps;
  axis.outputs = axis.full ? length - 2 * kSsimRadius : length;
  axis.weights.assign(static_cast<size_t>(axis.outputs) * kSsimTaps, 0.0);
  for (int o = 0; o < axis.outputs; ++o) {
    const int centre = axis.full ? o + kSsimRadius : o;
    const int lo = std::max(0, centre - kSsimRadius);
    const int hi = std::min(length - 1, centre + kSsimRadius);
    double sum = 0.0;
    for (int i = lo; i <= hi; ++i) sum += kTaps[static_cast<size_t>(i - centre + kSsimRadius)];
    for (int i = lo; i <= hi; ++i)
      axis.weights[static_cast<size_t>(o) * kSsimTaps + static_cast<size_t>(i - lo)] =
          axis.full ? kTaps[static_cast<size_t>(i - centre + kSsimRadius)]
                    : kTaps[static_cast<size_t>(i - centre + kSsimRadius)] / sum;
    axis.first.push_back(lo);
    axis.count.push_back(hi - lo + 1);
  }
  return axis;
}

// The five local moments E[x], E[y], E[x²], E[y²], E[xy], as separate planes.
constexpr int kMoments = 5;

// Mean SSIM of one channel over the evaluated window positions. Output rows are done in
// strips (each strip filters the input rows it needs, so memory stays small); every output
// value is computed the same way whatever the strip or thread, and the per-row sums are
// added in row order, so the result is deterministic.
double ssimChannel(const ImageF& test, const ImageF& ref, int channel, const WindowAxis& ax,
                   const WindowAxis& ay) {
  const int w = test.width;
  const size_t outW = static_cast<size_t>(ax.outputs);
  constexpr int kStrip = 32;
  const int strips = (ay.outputs + kStrip - 1) / kStrip;
  std::vector<double> rowSums(static_cast<size_t>(ay.outputs), 0.0);

  parallelFor(0, strips, [&](int strip) {
    const int oy0 = strip * kStrip;
    const int oy1 = std::min(ay.outputs, oy0 + kStrip);
    const int yBegin = ay.first[static_cast<size_t>(oy0)];
    const int yEnd = ay.first[static_cast<size_t>(oy1 - 1)] + ay.count[static_cast<size_t>(oy1 - 1)];
    const size_t rows = static_cast<size_t>(yEnd - yBegin);
    const size_t plane = rows * outW;

    // Horizontal pass over the strip's input rows.
    std::vector<double> horizontal(kMoments * plane, 0.0);
    std::vector<double> products(static_cast<size_t>(kMoments) * w);
    for (int y = yBegin; y < yEnd; ++y) {
      double* p[kMoments];
      for (int j = 0; j < kMoments; ++j) p[j] = &products[static_cast<size_t>(j) * w];
      for (int x = 0; x < w; ++x) {
        const double a = test.at(x, y, channel);
        const double b = ref.at(x, y, channel);
        p[0][x] = a;
        p[1][x] = b;
        p[2][x] = a * a;
        p[3][x] = b * b;
        p[4][x] = a * b;
      }
      const size_t rowOffset = static_cast<size_t>(y - yBegin) * outW;
      for (int j = 0; j < kMoments; ++j) {
        double* out = &horizontal[static_cast<size_t>(j) * plane + rowOffset];
        const double* in = p[j];
        if (ax.full) {
          for (int k = 0; k < kSsimTaps; ++k) {
            const double t = ax.weight(0, k);
            for (size_t o = 0; o < outW; ++o) out[o] += t * in[o + static_cast<size_t>(k)];
          }
        } else {
          for (size_t o = 0; o < outW; ++o) {
            const int oi = static_cast<int>(o);
            for (int k = 0; k < ax.count[o]; ++k)
              out[o] += ax.weight(oi, k) * in[ax.first[o] + k];
          }
        }
      }
    }

    // Vertical pass and the SSIM map, one output row at a time.
    std::vector<double> moments(kMoments * outW);
    for (int oy = oy0; oy < oy1; ++oy) {
      std::fill(moments.begin(), moments.end(), 0.0);
      for (int k = 0; k < ay.count[static_cast<size_t>(oy)]; ++k) {
        const double t = ay.weight(oy, k);
        const size_t row = static_cast<size_t>(ay.first[static_cast<size_t>(oy)] + k - yBegin);
        for (int j = 0; j < kMoments; ++j) {
          double* m = &moments[static_cast<size_t>(j) * outW];
          const double* src = &horizontal[static_cast<size_t>(j) * plane + row * outW];
          for (size_t o = 0; o < outW; ++o) m[o] += t * src[o];
        }
      }
      double rowSum = 0.0;
      for (size_t o = 0; o < outW; ++o) {
        const double ux = moments[o];
        const double uy = moments[outW + o];
        // Population (co)variances, as Wang et al. and use_sample_covariance=False.
        const double vx = moments[2 * outW + o] - ux * ux;
        const double vy = moments[3 * outW + o] - uy * uy;
        const double vxy = moments[4 * outW + o] - ux * uy;
        const double num = (2.0 * ux * uy + kSsimC1) * (2.0 * vxy + kSsimC2);
        const double den = (ux * ux + uy * uy + kSsimC1) * (vx + vy + kSsimC2);
        rowSum += num / den;
      }
      rowSums[static_cast<size_t>(oy)] = rowSum;
    }
  });

  double sum = 0.0;
  for (double value : rowSums) sum += value;
  return sum / (static_cast<double>(ax.outputs) * static_cast<double>(ay.outputs));
}
}  // namespace

double rmsError(const ImageF& test, const ImageF& ref) {
  requireComparable(test, ref, "rms");
  return std::sqrt(meanSquaredError(test, ref));
}

double meanAbsError(const ImageF& test, const ImageF& ref) {
  requireComparable(test, ref, "mean |error|");
  double sum = 0.0;  // in index order: the same sum for any thread count
  for (size_t i = 0; i < test.data.size(); ++i) sum += std::abs(static_cast<double>(test.data[i]) - ref.data[i]);
  return test.data.empty() ? 0.0 : sum / static_cast<double>(test.data.size());
}

double maxAbsError(const ImageF& test, const ImageF& ref) {
  requireComparable(test, ref, "max |error|");
  const size_t rowLength = static_cast<size_t>(test.width) * test.channels;
  std::vector<double> rowMax(static_cast<size_t>(test.height), 0.0);
  parallelFor(tbb::blocked_range<int>(0, test.height), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y != r.end(); ++y) {
      const size_t begin = static_cast<size_t>(y) * rowLength;
      double m = 0.0;
      for (size_t i = begin; i < begin + rowLength; ++i) {
        const double d =
            std::abs(static_cast<double>(test.data[i]) - static_cast<double>(ref.data[i]));
        // A NaN anywhere must show, not be skipped by the comparison.
        if (std::isnan(d) || d > m) m = d;
        if (std::isnan(m)) break;
      }
      rowMax[static_cast<size_t>(y)] = m;
    }
  });
  double result = 0.0;
  for (double m : rowMax) {
    if (std::isnan(m)) return m;
    result = std::max(result, m);
  }
  return result;
}

double psnr(const ImageF& test, const ImageF& ref) {
  requireComparable(test, ref, "psnr");
  const double mse = meanSquaredError(test, ref);
  if (mse == 0.0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(1.0 / mse);
}

double ssim(const ImageF& test, const ImageF& ref) {
  requireComparable(test, ref, "ssim");
  const WindowAxis ax = windowAxis(test.width);
  const WindowAxis ay = windowAxis(test.height);
  double sum = 0.0;
  for (int c = 0; c < test.channels; ++c) sum += ssimChannel(test, ref, c, ax, ay);
  return sum / static_cast<double>(test.channels);
}

ImageU8 transitionBand(const ImageU8& labels, int radius) {
  require(radius >= 0, "transition band: negative radius " + std::to_string(radius));
  const int w = labels.width;
  const int h = labels.height;
  ImageU8 band(w, h, 1, 0);
  if (w <= 0 || h <= 0) return band;

  // Labels differ when any channel differs (labels are normally one channel).
  auto differs = [&](int x0, int y0, int x1, int y1) {
    for (int c = 0; c < labels.channels; ++c)
      if (labels.at(x0, y0, c) != labels.at(x1, y1, c)) return true;
    return false;
  };
  ImageU8 transition(w, h, 1, 0);
  parallelFor(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const bool t = (x > 0 && differs(x, y, x - 1, y)) || (x + 1 < w && differs(x, y, x + 1, y)) ||
                     (y > 0 && differs(x, y, x, y - 1)) || (y + 1 < h && differs(x, y, x, y + 1));
      transition.at(x, y) = t ? 1 : 0;
    }
  });

  // Chebyshev dilation is separable: a (2r+1)-wide box in x, then in y. Each uses the
  // distance to the nearest set pixel on the left and on the right (O(w) per row).
  auto dilateLine = [radius](const uint8_t* in, uint8_t* out, int n, size_t stride) {
    int last = std::numeric_limits<int>::min() / 2;  // index of the last set pixel seen
    for (int i = 0; i < n; ++i) {
      if (in[static_cast<size_t>(i) * stride]) last = i;
      out[static_cast<size_t>(i) * stride] = (i - last <= radius) ? 1 : 0;
    }
    last = std::numeric_limits<int>::max() / 2;
    for (int i = n - 1; i >= 0; --i) {
      if (in[static_cast<size_t>(i) * stride]) last = i;
      if (last - i <= radius) out[static_cast<size_t>(i) * stride] = 1;
    }
  };
  ImageU8 rows(w, h, 1, 0);
  parallelFor(0, h, [&](int y) {
    dilateLine(&transition.at(0, y), &rows.at(0, y), w, 1);
  });
  parallelFor(0, w, [&](int x) {
    dilateLine(&rows.at(x, 0), &band.at(x, 0), h, static_cast<size_t>(w));
  });
  return band;
}

double maskedRms(const ImageF& test, const ImageF& ref, const ImageU8& band) {
  requireComparable(test, ref, "edge-band rms");
  require(band.width == test.width && band.height == test.height && band.channels == 1,
          "edge-band rms: band is " + std::to_string(band.width) + "x" +
              std::to_string(band.height) + "x" + std::to_string(band.channels) +
              ", image is " + sizeText(test));
  const int channels = test.channels;
  std::vector<double> rowSum(static_cast<size_t>(test.height), 0.0);
  std::vector<int64_t> rowCount(static_cast<size_t>(test.height), 0);
  parallelFor(0, test.height, [&](int y) {
    double s = 0.0;
    int64_t n = 0;
    for (int x = 0; x < test.width; ++x) {
      if (!band.at(x, y)) continue;
      ++n;
      for (int c = 0; c < channels; ++c) {
        const double d =
            static_cast<double>(test.at(x, y, c)) - static_cast<double>(ref.at(x, y, c));
        s += d * d;
      }
    }
    rowSum[static_cast<size_t>(y)] = s;
    rowCount[static_cast<size_t>(y)] = n;
  });
  double sum = 0.0;
  int64_t pixels = 0;
  for (size_t y = 0; y < rowSum.size(); ++y) {
    sum += rowSum[y];
    pixels += rowCount[y];
  }
  if (pixels == 0) return 0.0;
  return std::sqrt(sum / (static_cast<double>(pixels) * channels));
}

ErrorFigures compareToReference(const ImageF& test, const ImageF& ref, const ImageU8& labels) {
  requireComparable(test, ref, "compare");
  ErrorFigures figures;
  const double mse = meanSquaredError(test, ref);
  figures.rms = std::sqrt(mse);
  figures.psnr = mse == 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
  figures.ssim = ssim(test, ref);
  figures.maxAbs = maxAbsError(test, ref);
  // No labels (e.g. a method without masks) means no transitions and an empty band.
  if (labels.empty()) return figures;
  require(labels.width == test.width && labels.height == test.height,
          "compare: label image is " + std::to_string(labels.width) + "x" +
              std::to_string(labels.height) + ", image is " + sizeText(test));
  const ImageU8 band = transitionBand(labels, 4);
  figures.edgeBandRms = maskedRms(test, ref, band);
  for (uint8_t b : band.data) figures.edgeBandPixels += b ? 1 : 0;
  return figures;
}

void FlickerMeter::add(const ImageF& test, const ImageF& ref) {
  require(test.width == ref.width && test.height == ref.height && test.channels == ref.channels,
          "flicker: the frame and its reference differ in size");
  const bool first = frames_ == 0;
  ImageF error(test.width, test.height, test.channels);
  for (size_t i = 0; i < error.data.size(); ++i) error.data[i] = test.data[i] - ref.data[i];
  if (!first) {
    require(previousError_.data.size() == error.data.size(), "flicker: frames of a path differ in size");
    for (size_t i = 0; i < error.data.size(); ++i)
      sum_ += std::abs(static_cast<double>(error.data[i]) - static_cast<double>(previousError_.data[i]));
    count_ += static_cast<int64_t>(error.data.size());
  }
  rmsSum_ += rmsError(test, ref);
  previousError_ = std::move(error);
  ++frames_;
  if (!withFlip_) return;
  FlipResult f = flip(ref, test);
  if (!first) {
    double s = 0.0;  // in index order: the same sum for any thread count
    for (size_t i = 0; i < f.errorMap.data.size(); ++i)
      s += std::abs(static_cast<double>(f.errorMap.data[i]) - static_cast<double>(previousFlip_.data[i]));
    flipSum_ += s;
    flipCount_ += static_cast<int64_t>(f.errorMap.data.size());
  }
  flipMeanSum_ += f.stats.mean;
  previousFlip_ = std::move(f.errorMap);
}

double FlickerMeter::flipFlicker() const { return flipCount_ > 0 ? flipSum_ / static_cast<double>(flipCount_) : 0.0; }

double FlickerMeter::meanFlip() const { return frames_ > 0 ? flipMeanSum_ / frames_ : 0.0; }

double FlickerMeter::flicker() const { return count_ > 0 ? sum_ / static_cast<double>(count_) : 0.0; }

double FlickerMeter::meanRms() const { return frames_ > 0 ? rmsSum_ / frames_ : 0.0; }

}  // namespace mrr
