#include "cpu_ref/bilateral.h"

#include <tbb/blocked_range2d.h>
#include "common/parallel.h"

#include <algorithm>
#include <cmath>

namespace mrr {

// max(N_p·N_q, 0)^p: by repeated squaring when p is a whole number (the default 16), which is
// exact to a few ulp and ~10× cheaper than powf on the hot path.
float normalSimilarity(float cosine, float power) {
  const int whole = static_cast<int>(power);
  if (static_cast<float>(whole) != power || whole < 0 || whole > 64) return std::pow(cosine, power);
  float result = 1.0f, base = cosine;
  for (int e = whole; e > 0; e >>= 1) {
    if (e & 1) result *= base;
    base *= base;
  }
  return result;
}

float bilateralWeight(const GBuffer& g, const ImageU8& stencil, const Constants::Bilateral& b, float spatial, int px,
                      int py, int qx, int qy) {
  if (!stencil.at(qx, qy) || !g.hit.at(qx, qy)) return 0.0f;
  // 1. depth similarity, relative to the centre's depth
  const float zp = g.depth.at(px, py);
  const float dz = (g.depth.at(qx, qy) - zp) / (b.sigmaDepth * zp);
  const float depthWeight = std::exp(-dz * dz);
  // 2. normal similarity
  const float cosine = std::max(glm::dot(g.normalAt(px, py), g.normalAt(qx, qy)), 0.0f);
  const float normalWeight = normalSimilarity(cosine, b.normalPower);
  // 3. spatial Gaussian × depth × normal
  return spatial * depthWeight * normalWeight;
}

ImageF bilateralBlur(const ImageF& image, const ImageU8& stencil, const GBuffer& g, const Constants::Bilateral& b) {
  if (b.radius == 0) return image;
  ImageF out = image;
  const int r = b.radius, side = 2 * r + 1;
  parallelFor(tbb::blocked_range2d<int>(0, image.height, 32, 0, image.width, 32),
                    [&](const tbb::blocked_range2d<int>& range) {
                      for (int y = range.rows().begin(); y != range.rows().end(); ++y)
                        for (int x = range.cols().begin(); x != range.cols().end(); ++x) {
                          if (!stencil.at(x, y) || !g.hit.at(x, y)) continue;
                          float weightSum = 0.0f;
                          float sum[4] = {0.0f, 0.0f, 0.0f, 0.0f};
                          for (int j = -r; j <= r; ++j)
                            for (int i = -r; i <= r; ++i) {
                              const int qx = x + i, qy = y + j;
                              if (!image.contains(qx, qy)) continue;
                              const float w = bilateralWeight(
                                  g, stencil, b, b.spatial[static_cast<size_t>((j + r) * side + i + r)], x, y, qx, qy);
                              if (w == 0.0f) continue;
                              weightSum += w;
                              for (int c = 0; c < image.channels; ++c) sum[c] += w * image.at(qx, qy, c);
                            }
                          // 4. normalise over the valid taps (the centre always is one, with weight 1)
                          for (int c = 0; c < image.channels; ++c) out.at(x, y, c) = sum[c] / weightSum;
                        }
                    });
  return out;
}

}  // namespace mrr
