#pragma once
// SPEC §12.4: mrr-effect's a-posteriori term with a budget in predicted time. Each candidate (a
// pixel q of the next coarser level n whose result varies over its 3×3 neighbourhood, SPEC §12.2's
// v(q)) is priced by SPEC §11's cost model: the predicted cost of the level-ℓ pixels its mark can
// add to S_ℓ, each by what the effect costs there, in whole units. The candidates above a priority
// threshold are marked, the lowest threshold whose total price fits the level's share. These are
// the readable host forms; the port makes the same on the GPU (refinement_budget.frag), and both
// paths' marks are exact against each other.
#include <cstdint>
#include <vector>

#include "common/cost_model.h"
#include "common/frame.h"

namespace mrr {

// Step 1, the units. One unit is full's predicted rest / 2^28 (`fullNs`, ns; 1 ns a unit where
// that is not positive), so a frame's budget is a whole number of units below 2^32 and a price
// resolves a small fraction of one pixel's cost at any size up to 4K.
double budgetUnitNs(double fullNs);
// ns in units, rounded down and held below 2^32 − 1 (the port's sums saturate there).
uint32_t budgetUnits(double ns, double unitNs);
// The class prices in units, rounded to nearest, each at most 2^20 (a window's sum stays exact).
UnitPrices unitPrices(const PixelPrices& prices, double unitNs);
// A level's share of what is left: left / (the refined levels from it down), rounded down.
uint32_t levelShare(uint32_t left, int levelsLeft);

// Step 2: each level-n pixel q's price: the level-ℓ pixels its mark can add to S_ℓ, those with
// S_ℓ = 0 within the blur's reach r_ℓ of its 2^{n−ℓ} × 2^{n−ℓ} children (clipped to the level), each
// at its class's price (a level-ℓ pixel on geometry where full-res pixel levelSamplePixel is; PCF's
// class from SSM's sample, pcfSampleValue, where there is one); the sum held at 2^32 − 1.
// Row-major, level n's grid.
std::vector<uint32_t> candidatePrices(const ImageU8& finerStencil, const ImageU8& fullResHit, const ImageU8& pcfSample,
                                      const Constants& constants, int level, int coarser, const UnitPrices& prices);

// Step 3, the priority: a key that grows with v / price, from the floats' and the price's bits
// alone (exact on both paths): (bits(v) >> (23 − kBudgetKeyBits)) − log key(price) + kBudgetKeyOffset
// (+ `bonus` for a candidate the previous frame marked, SPEC §14.2), held in [0, kBudgetKeys − 2];
// a free candidate (price 0) takes kBudgetKeys − 1. v > 0.
uint32_t priorityKey(float v, uint32_t price, uint32_t bonus);
// The price's log key: 2^kBudgetKeyBits × ⌊log2 price⌋ + the kBudgetKeyBits bits below its top bit.
uint32_t priceKey(uint32_t price);
// SPEC §14.2's bonus in keys: kBudgetKeyBits steps an octave of 1 / (1 − h), rounded (0 for h = 0).
uint32_t hysteresisBonus(float hysteresis);

// Step 4, the selection. A candidate is a level-n pixel with v(q) > τ (or, SPEC §14.2, v(q) >
// (1 − h) τ where `previous` says the previous frame marked it). S(T) is the total price of the
// candidates whose key is at least T (held at 2^32 − 1); the threshold is the least T in
// [0, kBudgetKeys] with S(T) ≤ `share`, and the candidates with a key of at least it are marked.
// So a free candidate is always marked, and all are where their total fits.
struct RefinementSelection {
  ImageU8 varies;           // the marks (level n's grid)
  uint32_t threshold = 0;   // T
  uint32_t spent = 0;       // S(T), in units
  int64_t candidates = 0;   // v(q) over its threshold
  int64_t taken = 0;
  int64_t kept = 0;         // of the taken, marked by the previous frame too (SPEC §14.2)
  std::vector<uint32_t> prices;  // what it selected with (candidatePrices), kept for compare and probe
};
RefinementSelection selectRefinement(const ImageF& range, const std::vector<uint32_t>& prices, uint32_t share,
                                     float tau, float hysteresis, const ImageU8* previous);

}  // namespace mrr
