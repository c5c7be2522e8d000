#include "compare/metrics/metrics.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"

namespace mrr {
namespace {

// skimage 0.19.3 (Debian python3-skimage), on the pair made by hashPair(32, 24, 3) below,
// as float64 arrays of shape (24, 32, 3):
//   structural_similarity(a, b, gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
//                         data_range=1.0, channel_axis=2)       -> 0.9210701920467411
//   the same on channel 0 only (a[:,:,0], b[:,:,0])            -> 0.9174647648415366
// The Python generator is the same integer formula as hash24 below, with a/b filled as
// a[y,x,c] = hash24(i,1)/2^24, b[y,x,c] = ((3*hash24(i,1) + hash24(i,2)) // 4)/2^24 and
// i = (y*W + x)*C + c. Both sides compute in double; only summation order differs.
constexpr double kSkimageSsimRgb = 0.9210701920467411;
constexpr double kSkimageSsimChannel0 = 0.9174647648415366;
constexpr double kSkimageTolerance = 1e-10;

// A 24-bit integer hash, exactly reproducible in numpy (all arithmetic mod 2^32).
uint32_t hash24(uint32_t i, uint32_t seed) {
  uint32_t v = i * 2654435761u + seed * 0x9E3779B9u;
  v ^= v >> 15;
  v *= 0x2C1B3C6Du;
  v ^= v >> 12;
  v *= 0x297A2D39u;
  v ^= v >> 15;
  return v >> 8;
}

// A noise image and a correlated copy; every value is k/2^24, exact in float.
void hashPair(int w, int h, int c, ImageF& a, ImageF& b) {
  a = ImageF(w, h, c);
  b = ImageF(w, h, c);
  for (size_t i = 0; i < a.data.size(); ++i) {
    const uint32_t ha = hash24(static_cast<uint32_t>(i), 1);
    const uint32_t hn = hash24(static_cast<uint32_t>(i), 2);
    a.data[i] = static_cast<float>(ha) / 16777216.0f;
    b.data[i] = static_cast<float>((3u * ha + hn) / 4u) / 16777216.0f;
  }
}

ImageF channel(const ImageF& image, int c) {
  ImageF out(image.width, image.height, 1);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) out.at(x, y) = image.at(x, y, c);
  return out;
}

ImageU8 labelsFrom(const std::vector<std::string>& rows) {
  ImageU8 image(static_cast<int>(rows[0].size()), static_cast<int>(rows.size()), 1);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      image.at(x, y) = static_cast<uint8_t>(rows[static_cast<size_t>(y)][static_cast<size_t>(x)] - '0');
  return image;
}

std::vector<std::string> rowsOf(const ImageU8& image) {
  std::vector<std::string> rows;
  for (int y = 0; y < image.height; ++y) {
    std::string row;
    for (int x = 0; x < image.width; ++x) row += static_cast<char>('0' + image.at(x, y));
    rows.push_back(row);
  }
  return rows;
}

TEST(Metrics, IdenticalImages) {
  ImageF a, b;
  hashPair(32, 24, 3, a, b);
  EXPECT_EQ(rmsError(a, a), 0.0);
  EXPECT_EQ(maxAbsError(a, a), 0.0);
  EXPECT_EQ(meanAbsError(a, a), 0.0);
  EXPECT_EQ(psnr(a, a), std::numeric_limits<double>::infinity());
  EXPECT_DOUBLE_EQ(ssim(a, a), 1.0);
  const ErrorFigures f = compareToReference(a, a, ImageU8(32, 24, 1, 0));
  EXPECT_EQ(f.rms, 0.0);
  EXPECT_TRUE(std::isinf(f.psnr));
  EXPECT_DOUBLE_EQ(f.ssim, 1.0);
  EXPECT_EQ(f.maxAbs, 0.0);
  EXPECT_EQ(f.edgeBandRms, 0.0);
  EXPECT_EQ(f.edgeBandPixels, 0);
}

TEST(Metrics, ConstantOffset) {
  const ImageF ref(13, 9, 3, 0.5f);
  const ImageF test(13, 9, 3, 0.6f);
  const double delta = static_cast<double>(0.6f) - 0.5;  // 0.1 up to float rounding
  EXPECT_NEAR(rmsError(test, ref), 0.1, 1e-6);
  EXPECT_NEAR(rmsError(test, ref), delta, 1e-14);
  EXPECT_EQ(maxAbsError(test, ref), delta);
  EXPECT_NEAR(psnr(test, ref), 20.0, 1e-5);
}

// Mean |Δ| weighs every error by its size where RMS weighs it by its square: half the pixels
// off by 0.2 and half exact give 0.1 against an RMS of 0.2/√2.
TEST(Metrics, MeanAbsErrorIsTheMeanOfTheErrorsSizes) {
  const ImageF ref(8, 4, 2, 0.5f);
  ImageF test = ref;
  for (size_t i = 0; i < test.data.size(); i += 2) test.data[i] = i % 4 == 0 ? 0.7f : 0.3f;  // ±0.2, either sign
  const double d = static_cast<double>(0.7f) - 0.5;
  EXPECT_NEAR(meanAbsError(test, ref), 0.5 * d, 1e-7);
  EXPECT_NEAR(rmsError(test, ref), d / std::sqrt(2.0), 1e-7);
  EXPECT_THROW(meanAbsError(ImageF(8, 4, 1, 0.0f), ref), MrrError);
}

TEST(Metrics, SsimOfConstantImagesIsTheLuminanceTerm) {
  // With no variance the contrast-structure term is C2/C2 = 1, leaving
  // (2ab + C1) / (a² + b² + C1) at every window position. The tolerance allows for the
  // cancellation in E[x²] − E[x]² (about 1e-16 each), as in skimage.
  const double c1 = 0.01 * 0.01;
  auto expected = [c1](double a, double b) { return (2 * a * b + c1) / (a * a + b * b + c1); };
  EXPECT_NEAR(ssim(ImageF(16, 12, 1, 0.5f), ImageF(16, 12, 1, 0.25f)), expected(0.5, 0.25), 1e-12);
  // Smaller than the window (clipped-window fallback), down to 1×1: same value.
  EXPECT_NEAR(ssim(ImageF(5, 3, 1, 0.5f), ImageF(5, 3, 1, 0.25f)), expected(0.5, 0.25), 1e-12);
  EXPECT_NEAR(ssim(ImageF(1, 1, 1, 0.5f), ImageF(1, 1, 1, 0.25f)), expected(0.5, 0.25), 1e-12);
  EXPECT_NEAR(ssim(ImageF(1, 1, 1, 0.0f), ImageF(1, 1, 1, 0.0f)), 1.0, 1e-12);
  // Channels are averaged.
  ImageF rgbTest(12, 11, 3), rgbRef(12, 11, 3);
  const float t[3] = {0.5f, 0.75f, 1.0f}, r[3] = {0.25f, 0.75f, 0.5f};
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 12; ++x)
      for (int c = 0; c < 3; ++c) {
        rgbTest.at(x, y, c) = t[c];
        rgbRef.at(x, y, c) = r[c];
      }
  EXPECT_NEAR(ssim(rgbTest, rgbRef),
              (expected(0.5, 0.25) + expected(0.75, 0.75) + expected(1.0, 0.5)) / 3.0, 1e-12);
}

TEST(Metrics, SsimMatchesScikitImage) {
  ImageF a, b;
  hashPair(32, 24, 3, a, b);
  // Spot values printed by the Python generator, to catch a drifted formula early.
  EXPECT_NEAR(a.at(0, 0, 0), 0.24089462, 1e-8);
  EXPECT_NEAR(b.at(0, 0, 0), 0.33588403, 1e-8);
  EXPECT_NEAR(a.at(31, 23, 0), 0.75551468, 1e-8);
  EXPECT_NEAR(ssim(a, b), kSkimageSsimRgb, kSkimageTolerance);
  EXPECT_NEAR(ssim(channel(a, 0), channel(b, 0)), kSkimageSsimChannel0, kSkimageTolerance);
  EXPECT_DOUBLE_EQ(ssim(a, b), ssim(b, a));  // symmetric
}

// Straightforward 2D SSIM: each evaluated position weighs the Gaussian taps that fall
// inside the image, renormalised; an axis of >= 11 samples keeps the valid positions only.
double bruteForceSsim(const ImageF& a, const ImageF& b) {
  double g[11];  // unnormalised: the division by wsum normalises
  for (int i = 0; i < 11; ++i) g[i] = std::exp(-0.5 * (i - 5) * (i - 5) / 2.25);
  auto centres = [](int n) {
    std::vector<int> out;
    for (int i = (n >= 11 ? 5 : 0); i < (n >= 11 ? n - 5 : n); ++i) out.push_back(i);
    return out;
  };
  double sum = 0.0;
  int positions = 0;
  for (int c = 0; c < a.channels; ++c)
    for (int cy : centres(a.height))
      for (int cx : centres(a.width)) {
        double wsum = 0, ux = 0, uy = 0, uxx = 0, uyy = 0, uxy = 0;
        for (int y = cy - 5; y <= cy + 5; ++y)
          for (int x = cx - 5; x <= cx + 5; ++x) {
            if (!a.contains(x, y)) continue;
            const double wt = g[x - cx + 5] * g[y - cy + 5];
            const double p = a.at(x, y, c), q = b.at(x, y, c);
            wsum += wt;
            ux += wt * p;
            uy += wt * q;
            uxx += wt * p * p;
            uyy += wt * q * q;
            uxy += wt * p * q;
          }
        ux /= wsum, uy /= wsum, uxx /= wsum, uyy /= wsum, uxy /= wsum;
        const double c1 = 1e-4, c2 = 9e-4;
        sum += (2 * ux * uy + c1) * (2 * (uxy - ux * uy) + c2) /
               ((ux * ux + uy * uy + c1) * (uxx - ux * ux + uyy - uy * uy + c2));
        ++positions;
      }
  return sum / positions;
}

TEST(Metrics, SsimMatchesBruteForceIncludingSmallImages) {
  const int sizes[][2] = {{32, 24}, {11, 11}, {7, 4}, {20, 5}, {3, 15}, {1, 1}, {2, 1}};
  for (const auto& size : sizes) {
    ImageF a, b;
    hashPair(size[0], size[1], 2, a, b);
    EXPECT_NEAR(ssim(a, b), bruteForceSsim(a, b), 1e-12) << size[0] << "x" << size[1];
    EXPECT_NEAR(ssim(a, a), 1.0, 1e-12) << size[0] << "x" << size[1];
  }
}

TEST(Metrics, FiguresDoNotDependOnThreadCount) {
  ImageF a, b;
  hashPair(301, 77, 3, a, b);
  ImageU8 labels(301, 77, 1, 0);
  for (int y = 0; y < 77; ++y)
    for (int x = 0; x < 301; ++x) labels.at(x, y) = static_cast<uint8_t>(hash24(static_cast<uint32_t>(y * 301 + x), 3) % 3 == 0);
  const ErrorFigures many = compareToReference(a, b, labels);
  ErrorFigures one;
  tbb::task_arena arena(1);
  arena.execute([&] { one = compareToReference(a, b, labels); });
  EXPECT_EQ(many.rms, one.rms);
  EXPECT_EQ(many.psnr, one.psnr);
  EXPECT_EQ(many.ssim, one.ssim);
  EXPECT_EQ(many.maxAbs, one.maxAbs);
  EXPECT_EQ(many.edgeBandRms, one.edgeBandRms);
  EXPECT_EQ(many.edgeBandPixels, one.edgeBandPixels);
}

TEST(Metrics, TransitionBandStraightEdge) {
  const ImageU8 labels = labelsFrom({"0001111", "0001111", "0001111"});
  EXPECT_EQ(rowsOf(transitionBand(labels, 0)),
            (std::vector<std::string>{"0011000", "0011000", "0011000"}));
  EXPECT_EQ(rowsOf(transitionBand(labels, 1)),
            (std::vector<std::string>{"0111100", "0111100", "0111100"}));
  EXPECT_EQ(rowsOf(transitionBand(labels, 4)),
            (std::vector<std::string>{"1111111", "1111111", "1111111"}));
}

TEST(Metrics, TransitionBandIsolatedPixelAndCorner) {
  // One odd pixel: its plus-shaped transition set, dilated by a 3×3 box.
  const ImageU8 dot = labelsFrom({"000000000", "000000000", "000000000", "000000000",
                                  "000020000", "000000000", "000000000", "000000000",
                                  "000000000"});
  EXPECT_EQ(rowsOf(transitionBand(dot, 1)),
            (std::vector<std::string>{"000000000", "000000000", "000111000", "001111100",
                                      "001111100", "001111100", "000111000", "000000000",
                                      "000000000"}));
  // A corner pixel, radius 2: the band is clipped to the image.
  const ImageU8 corner = labelsFrom({"100000", "000000", "000000", "000000"});
  EXPECT_EQ(rowsOf(transitionBand(corner, 2)),
            (std::vector<std::string>{"111100", "111100", "111100", "111000"}));
  // Uniform labels: no band.
  EXPECT_EQ(rowsOf(transitionBand(labelsFrom({"333", "333"}), 4)),
            (std::vector<std::string>{"000", "000"}));
}

TEST(Metrics, TransitionBandMatchesBruteForce) {
  const int w = 37, h = 23, radius = 4;
  ImageU8 labels(w, h, 1, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      labels.at(x, y) = static_cast<uint8_t>(hash24(static_cast<uint32_t>(y * w + x), 7) % 17 == 0 ? 1 : 0);
  auto isTransition = [&](int x, int y) {
    const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k)
      if (labels.contains(x + dx[k], y + dy[k]) && labels.at(x + dx[k], y + dy[k]) != labels.at(x, y))
        return true;
    return false;
  };
  const ImageU8 band = transitionBand(labels, radius);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool near = false;
      for (int v = y - radius; v <= y + radius; ++v)
        for (int u = x - radius; u <= x + radius; ++u) near = near || (labels.contains(u, v) && isTransition(u, v));
      EXPECT_EQ(band.at(x, y) != 0, near) << x << "," << y;
    }
}

TEST(Metrics, MaskedRms) {
  const ImageF ref(4, 1, 1, 0.0f);
  ImageF test(4, 1, 1);
  const float values[4] = {0.5f, 0.25f, 0.75f, 1.0f};
  for (int x = 0; x < 4; ++x) test.at(x, 0) = values[x];
  ImageU8 band(4, 1, 1, 0);
  band.at(0, 0) = 1;
  band.at(2, 0) = 1;
  EXPECT_DOUBLE_EQ(maskedRms(test, ref, band), std::sqrt((0.25 + 0.5625) / 2.0));
  EXPECT_EQ(maskedRms(test, ref, ImageU8(4, 1, 1, 0)), 0.0);
  EXPECT_DOUBLE_EQ(maskedRms(test, ref, ImageU8(4, 1, 1, 1)), rmsError(test, ref));
  // Two channels: the mean runs over band pixels × channels.
  ImageF test2(2, 1, 2, 0.0f);
  test2.at(0, 0, 0) = 0.5f;
  ImageU8 band2(2, 1, 1, 0);
  band2.at(0, 0) = 1;
  EXPECT_DOUBLE_EQ(maskedRms(test2, ImageF(2, 1, 2, 0.0f), band2), std::sqrt(0.25 / 2.0));
  EXPECT_THROW(maskedRms(test, ref, ImageU8(3, 1, 1, 1)), MrrError);
}

TEST(Metrics, CompareToReferenceFillsEveryFigure) {
  ImageF a, b;
  hashPair(32, 24, 3, a, b);
  ImageU8 labels(32, 24, 1, 0);
  for (int y = 0; y < 24; ++y)
    for (int x = 16; x < 32; ++x) labels.at(x, y) = 1;  // one vertical edge between x=15 and 16
  const ErrorFigures f = compareToReference(a, b, labels);
  EXPECT_DOUBLE_EQ(f.rms, rmsError(a, b));
  EXPECT_DOUBLE_EQ(f.psnr, psnr(a, b));
  EXPECT_DOUBLE_EQ(f.ssim, ssim(a, b));
  EXPECT_DOUBLE_EQ(f.maxAbs, maxAbsError(a, b));
  const ImageU8 band = transitionBand(labels, 4);
  EXPECT_EQ(f.edgeBandPixels, 10 * 24);  // columns 11..20
  EXPECT_DOUBLE_EQ(f.edgeBandRms, maskedRms(a, b, band));
  EXPECT_GT(f.rms, 0.0);
  EXPECT_GT(f.edgeBandRms, 0.0);
  EXPECT_THROW(compareToReference(a, b, ImageU8(31, 24, 1, 0)), MrrError);
}

TEST(Metrics, SizeMismatchThrows) {
  const ImageF a(8, 8, 3), wider(9, 8, 3), grey(8, 8, 1);
  EXPECT_THROW(rmsError(a, wider), MrrError);
  EXPECT_THROW(maxAbsError(a, grey), MrrError);
  EXPECT_THROW(psnr(wider, a), MrrError);
  EXPECT_THROW(ssim(a, grey), MrrError);
  EXPECT_THROW(compareToReference(a, wider, ImageU8()), MrrError);
  EXPECT_THROW(rmsError(ImageF(), ImageF()), MrrError);
}

}  // namespace
}  // namespace mrr
