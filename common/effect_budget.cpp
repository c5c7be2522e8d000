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
  // 1a. each level-ℓ pixel with S_ℓ = 0 by its class: paying, paying PCF or leaving (−1: S_ℓ = 1)
  enum { kPaying, kPcf, kLeaving, kClasses };
  const auto classOf = [&](int x, int y) {
    if (finerStencil.at(x, y)) return -1;
    if (!levelPixelHit(fullResHit, x, y, fine.scale)) return static_cast<int>(kLeaving);
    if (pcfSample.empty()) return static_cast<int>(kPaying);
    const uint8_t cls = static_cast<uint8_t>(
        pcfSampleValue(pcfSample, std::min(levelSamplePixel(x, fine.scale), fullResHit.width - 1),
                       std::min(levelSamplePixel(y, fine.scale), fullResHit.height - 1)) &
        ((1u << kPcfSampleClassBits) - 1u));
    return static_cast<int>(cls == kPcfSampleNone ? kLeaving : cls == kPcfSamplePcf ? kPcf : kPaying);
  };
  // 1b. a candidate's window: its children, widened by the blur's reach r_ℓ, clipped. The windows
  // of a row of candidates span the same rows, and those rows only move down from one candidate
  // row to the next: per column, each class's count over the window's rows, rows entering and
  // leaving as it slides; then along the row, prefix sums of those. Whole numbers, so a window's
  // count is exact (a summed-area table of the level gives the same counts, and cost a frame
  // page faults on its fresh megabytes).
  const size_t columns = static_cast<size_t>(w) * kClasses;
  std::vector<int32_t> column(columns, 0), prefix(columns + kClasses, 0);
  const auto slide = [&](int y, int32_t sign) {
    for (int x = 0; x < w; ++x) {
      const int k = classOf(x, y);
      if (k >= 0) column[static_cast<size_t>(x) * kClasses + static_cast<size_t>(k)] += sign;
    }
  };
  // 1c. its price: the classes' counts there times their prices
  const double price[kClasses] = {prices.paying, prices.pcf, prices.leaving};
  std::vector<double> out(static_cast<size_t>(coarse.width) * static_cast<size_t>(coarse.height));
  int top = 0, bottom = 0;  // the rows [top, bottom) in `column`
  for (int qy = 0; qy < coarse.height; ++qy) {
    const int y0 = std::max(0, qy * ratio - r), y1 = std::min(h, (qy + 1) * ratio + r);
    for (; bottom < y1; ++bottom) slide(bottom, 1);
    for (; top < y0; ++top) slide(top, -1);
    for (size_t i = 0; i < columns; ++i) prefix[i + kClasses] = prefix[i] + column[i];
    for (int qx = 0; qx < coarse.width; ++qx) {
      const int x0 = std::max(0, qx * ratio - r), x1 = std::min(w, (qx + 1) * ratio + r);
      double sum = 0.0;
      for (size_t k = 0; k < kClasses; ++k)
        sum += static_cast<double>(prefix[static_cast<size_t>(x1) * kClasses + k] -
                                   prefix[static_cast<size_t>(x0) * kClasses + k]) *
               price[k];
      out[static_cast<size_t>(qy) * static_cast<size_t>(coarse.width) + static_cast<size_t>(qx)] = sum;
    }
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
  const auto over = [&](size_t i) {
    const bool before = sticky && previous->data[i] != 0;
    return range.data[i] > (before ? keepTau : tau);
  };
  std::vector<Candidate> candidates;
  size_t count = 0;
  for (size_t i = 0; i < range.data.size(); ++i) count += over(i) ? 1 : 0;
  candidates.reserve(count);
  for (size_t i = 0; i < range.data.size(); ++i) {
    if (!over(i)) continue;
    const bool before = sticky && previous->data[i] != 0;
    const float v = range.data[i];
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
  // (by priority, then index: the order a stable sort by priority gives the row-major list, without
  // its buffer)
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return a.priority > b.priority || (a.priority == b.priority && a.index < b.index);
  });
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
