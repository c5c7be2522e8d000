#include "common/effect_budget.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "common/shader_constants.h"

namespace mrr {

namespace {
constexpr uint32_t kSaturated = std::numeric_limits<uint32_t>::max();
constexpr double kUnitsPerFull = 268435456.0;  // 2^28
constexpr uint32_t kMostClassPrice = 1u << 20;
uint32_t saturate(uint64_t sum) { return sum >= kSaturated ? kSaturated : static_cast<uint32_t>(sum); }
}  // namespace

double budgetUnitNs(double fullNs) { return fullNs > 0.0 ? fullNs / kUnitsPerFull : 1.0; }

uint32_t budgetUnits(double ns, double unitNs) {
  if (!(ns > 0.0)) return 0;
  const double units = std::floor(ns / unitNs);
  return units >= static_cast<double>(kSaturated - 1) ? kSaturated - 1 : static_cast<uint32_t>(units);
}

UnitPrices unitPrices(const PixelPrices& p, double unitNs) {
  const auto units = [&](double ns) {
    const double u = std::round(std::max(0.0, ns) / unitNs);
    return u >= kMostClassPrice ? kMostClassPrice : static_cast<uint32_t>(u);
  };
  return {units(p.paying), units(p.pcf), units(p.leaving)};
}

uint32_t levelShare(uint32_t left, int levelsLeft) { return levelsLeft > 0 ? left / static_cast<uint32_t>(levelsLeft) : 0; }

std::vector<uint32_t> candidatePrices(const ImageU8& finerStencil, const ImageU8& fullResHit, const ImageU8& pcfSample,
                                      const Constants& c, int level, int coarser, const UnitPrices& prices) {
  const LevelConstants& fine = c.levels[static_cast<size_t>(level)];
  const LevelConstants& coarse = c.levels[static_cast<size_t>(coarser)];
  const int w = fine.width, h = fine.height, ratio = 1 << (coarser - level), r = fine.blurRadius;
  // 2a. each level-ℓ pixel's price: 0 where S_ℓ = 1, else its class's: paying, paying PCF or leaving
  const auto priceOf = [&](int x, int y) -> uint64_t {
    if (finerStencil.at(x, y)) return 0;
    if (!levelPixelHit(fullResHit, x, y, fine.scale)) return prices.leaving;
    if (pcfSample.empty()) return prices.paying;
    const uint8_t cls = pcfSampleClass(
        pcfSampleValue(pcfSample, std::min(levelSamplePixel(x, fine.scale), fullResHit.width - 1),
                       std::min(levelSamplePixel(y, fine.scale), fullResHit.height - 1)));
    return cls == kPcfSampleNone ? prices.leaving : cls == kPcfSamplePcf ? prices.pcf : prices.paying;
  };
  // 2b. a candidate's window: its children, widened by the blur's reach r_ℓ, clipped. The windows
  // of a row of candidates span the same rows, and those rows only move down from one candidate
  // row to the next: per column, the sum over the window's rows, rows entering and leaving as it
  // slides; then along the row, prefix sums of those. Whole numbers, so a window's sum is exact
  // (the port sums the rows, then the columns, refinement_budget.frag STEP 2 and 3).
  std::vector<uint64_t> column(static_cast<size_t>(w), 0), prefix(static_cast<size_t>(w) + 1, 0);
  const auto slide = [&](int y, bool enter) {
    for (int x = 0; x < w; ++x) {
      const uint64_t p = priceOf(x, y);
      if (enter) column[static_cast<size_t>(x)] += p;
      else column[static_cast<size_t>(x)] -= p;
    }
  };
  std::vector<uint32_t> out(static_cast<size_t>(coarse.width) * static_cast<size_t>(coarse.height));
  int top = 0, bottom = 0;  // the rows [top, bottom) in `column`
  for (int qy = 0; qy < coarse.height; ++qy) {
    const int y0 = std::max(0, qy * ratio - r), y1 = std::min(h, (qy + 1) * ratio + r);
    for (; bottom < y1; ++bottom) slide(bottom, true);
    for (; top < y0; ++top) slide(top, false);
    for (size_t x = 0; x < column.size(); ++x) prefix[x + 1] = prefix[x] + column[x];
    // 2c. its price: the sum over the window's columns, held at 2^32 − 1
    for (int qx = 0; qx < coarse.width; ++qx) {
      const int x0 = std::max(0, qx * ratio - r), x1 = std::min(w, (qx + 1) * ratio + r);
      out[static_cast<size_t>(qy) * static_cast<size_t>(coarse.width) + static_cast<size_t>(qx)] =
          saturate(prefix[static_cast<size_t>(x1)] - prefix[static_cast<size_t>(x0)]);
    }
  }
  return out;
}

uint32_t priceKey(uint32_t price) {
  const int top = std::bit_width(price) - 1;  // findMSB
  const uint32_t below = top >= kBudgetKeyBits ? price >> (top - kBudgetKeyBits) : price << (kBudgetKeyBits - top);
  return static_cast<uint32_t>(top) * (1u << kBudgetKeyBits) + (below & ((1u << kBudgetKeyBits) - 1u));
}

uint32_t priorityKey(float v, uint32_t price, uint32_t bonus) {
  if (price == 0) return kBudgetKeys - 1;
  const int64_t key = static_cast<int64_t>(std::bit_cast<uint32_t>(v) >> (23 - kBudgetKeyBits)) + kBudgetKeyOffset -
                      static_cast<int64_t>(priceKey(price)) + static_cast<int64_t>(bonus);
  return static_cast<uint32_t>(std::clamp<int64_t>(key, 0, kBudgetKeys - 2));
}

uint32_t hysteresisBonus(float h) {
  if (!(h > 0.0f)) return 0;
  const double octaves = -std::log2(1.0 - static_cast<double>(std::min(h, 0.999f)));
  return static_cast<uint32_t>(std::lround(octaves * (1 << kBudgetKeyBits)));
}

RefinementSelection selectRefinement(const ImageF& range, const std::vector<uint32_t>& prices, uint32_t share,
                                     float tau, float hysteresis, const ImageU8* previous) {
  RefinementSelection s;
  s.varies = ImageU8(range.width, range.height, 1, 0);
  const bool sticky = hysteresis > 0.0f && previous && previous->width == range.width && previous->height == range.height;
  const float keepTau = (1.0f - hysteresis) * tau;
  const uint32_t bonus = hysteresisBonus(hysteresis);
  // 4a. the candidates' keys (kBudgetKeys: not a candidate), and each key's total price
  std::vector<uint32_t> key(range.data.size(), kBudgetKeys);
  std::vector<uint64_t> total(kBudgetKeys + 1, 0);
  for (size_t i = 0; i < range.data.size(); ++i) {
    const bool before = sticky && previous->data[i] != 0;
    if (!(range.data[i] > (before ? keepTau : tau))) continue;
    key[i] = priorityKey(range.data[i], prices[i], before ? bonus : 0);
    total[key[i]] += prices[i];
    ++s.candidates;
  }
  // 4b. S(T) from the top key down; the least T whose S(T) fits (S(kBudgetKeys) = 0 always does)
  uint64_t above = 0;
  s.threshold = kBudgetKeys;
  for (int t = kBudgetKeys - 1; t >= 0; --t) {
    above += total[static_cast<size_t>(t)];
    if (saturate(above) > share) break;
    s.threshold = static_cast<uint32_t>(t);
    s.spent = saturate(above);
  }
  // 4c. the marks: the candidates at or above it
  for (size_t i = 0; i < key.size(); ++i) {
    if (key[i] == kBudgetKeys || key[i] < s.threshold) continue;
    s.varies.data[i] = 1;
    ++s.taken;
    if (sticky && previous->data[i]) ++s.kept;
  }
  return s;
}

}  // namespace mrr
