#include "common/effect_budget.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "common/shader_constants.h"

namespace mrr {

std::vector<double> candidatePrices(const ImageU8& finerStencil, const ImageU8& fullResHit, const ImageU8& pcfSample,
                                    const Constants& c, int level, int coarser, const PixelPrices& prices) {
  const LevelConstants& fine = c.levels[static_cast<size_t>(level)];
  const LevelConstants& coarse = c.levels[static_cast<size_t>(coarser)];
  const int w = fine.width, h = fine.height, ratio = 1 << (coarser - level), r = fine.blurRadius;
  // 1a. the level-ℓ pixels with S_ℓ = 0 of each class (paying, paying PCF, leaving), counted into
  // tables of prefix sums ((w + 1) × (h + 1), row-major): whole numbers, so a window's count is exact
  enum { kPaying, kPcf, kLeaving, kClasses };
  const size_t stride = static_cast<size_t>(w + 1);
  std::vector<int32_t> table(stride * static_cast<size_t>(h + 1) * kClasses, 0);
  const auto at = [&](int x, int y, int k) -> int32_t& {
    return table[(static_cast<size_t>(y) * stride + static_cast<size_t>(x)) * kClasses + static_cast<size_t>(k)];
  };
  for (int y = 0; y < h; ++y) {
    int32_t row[kClasses] = {0, 0, 0};
    for (int x = 0; x < w; ++x) {
      if (!finerStencil.at(x, y)) {
        int k = kPaying;
        if (!levelPixelHit(fullResHit, x, y, fine.scale)) {
          k = kLeaving;
        } else if (!pcfSample.empty()) {
          const uint8_t cls = static_cast<uint8_t>(
              pcfSampleValue(pcfSample, std::min(levelSamplePixel(x, fine.scale), fullResHit.width - 1),
                             std::min(levelSamplePixel(y, fine.scale), fullResHit.height - 1)) &
              ((1u << kPcfSampleClassBits) - 1u));
          k = cls == kPcfSampleNone ? kLeaving : cls == kPcfSamplePcf ? kPcf : kPaying;
        }
        ++row[k];
      }
      for (int k = 0; k < kClasses; ++k) at(x + 1, y + 1, k) = at(x + 1, y, k) + row[k];
    }
  }
  // 1b. a candidate's window: its children, widened by the blur's reach r_ℓ, clipped; its price the
  // classes' counts there times their prices
  const double price[kClasses] = {prices.paying, prices.pcf, prices.leaving};
  std::vector<double> out(static_cast<size_t>(coarse.width) * static_cast<size_t>(coarse.height));
  for (int qy = 0; qy < coarse.height; ++qy)
    for (int qx = 0; qx < coarse.width; ++qx) {
      const int x0 = std::max(0, qx * ratio - r), x1 = std::min(w, (qx + 1) * ratio + r);
      const int y0 = std::max(0, qy * ratio - r), y1 = std::min(h, (qy + 1) * ratio + r);
      double sum = 0.0;
      for (int k = 0; k < kClasses; ++k)
        sum += static_cast<double>(at(x1, y1, k) - at(x0, y1, k) - at(x1, y0, k) + at(x0, y0, k)) * price[k];
      out[static_cast<size_t>(qy) * static_cast<size_t>(coarse.width) + static_cast<size_t>(qx)] = sum;
    }
  return out;
}

RefinementSelection selectRefinement(const ImageF& range, const std::vector<double>& prices, double budgetNs, float tau,
                                     float hysteresis, const ImageU8* previous) {
  RefinementSelection s;
  s.varies = ImageU8(range.width, range.height, 1, 0);
  const bool sticky = hysteresis > 0.0f && previous && previous->width == range.width && previous->height == range.height;
  const float keepTau = (1.0f - hysteresis) * tau;
  // 2a. the candidates and their priorities
  struct Candidate {
    size_t index;
    double priority;
  };
  std::vector<Candidate> candidates;
  for (size_t i = 0; i < range.data.size(); ++i) {
    const bool before = sticky && previous->data[i] != 0;
    const float v = range.data[i];
    if (!(v > (before ? keepTau : tau))) continue;
    const double price = prices[i];
    double priority = price > 0.0 ? static_cast<double>(v) / price : std::numeric_limits<double>::infinity();
    if (before) priority /= (1.0 - static_cast<double>(hysteresis));
    candidates.push_back({i, priority});
  }
  s.candidates = static_cast<int64_t>(candidates.size());
  // 2b. most variation per nanosecond first (row-major among equals), each taken while it fits.
  // When every candidate fits, the order does not matter: all are taken (no sort).
  double all = 0.0;
  for (const Candidate& cand : candidates) all += prices[cand.index];
  if (all <= budgetNs) {
    for (const Candidate& cand : candidates) {
      s.spentNs += prices[cand.index];
      s.varies.data[cand.index] = 1;
      ++s.taken;
      if (sticky && previous->data[cand.index]) ++s.kept;
    }
    return s;
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.priority > b.priority; });
  for (const Candidate& cand : candidates) {
    const double price = prices[cand.index];
    if (s.spentNs + price > budgetNs) continue;
    s.spentNs += price;
    s.varies.data[cand.index] = 1;
    ++s.taken;
    if (sticky && previous->data[cand.index]) ++s.kept;
  }
  return s;
}

}  // namespace mrr
