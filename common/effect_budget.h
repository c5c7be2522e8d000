#pragma once
// SPEC §12.4: mrr-effect's a-posteriori term with a budget in predicted time. Each candidate (a
// pixel q of the next coarser level n whose result varies over its 3×3 neighbourhood, SPEC §12.2's
// v(q)) is priced by SPEC §11's cost model: the predicted nanoseconds of the level-ℓ pixels its mark
// can add to S_ℓ, each by what the effect costs there. The candidates with the most variation per
// nanosecond are marked first, while they fit the frame's budget. Host logic on host images, so both
// paths select the same marks from the same v (the oracle's v, the port's read back).
#include <cstdint>
#include <vector>

#include "common/cost_model.h"
#include "common/frame.h"

namespace mrr {

// Step 1: each level-n pixel q's price: the level-ℓ pixels its mark can add to S_ℓ, those with
// S_ℓ = 0 within the blur's reach r_ℓ of its 2^{n−ℓ} × 2^{n−ℓ} children (clipped to the level), each
// at its class's price (a level-ℓ pixel on geometry where full-res pixel levelSamplePixel is; PCF's
// class from SSM's sample, pcfSampleValue, where there is one). Row-major, level n's grid.
std::vector<double> candidatePrices(const ImageU8& finerStencil, const ImageU8& fullResHit, const ImageU8& pcfSample,
                                    const Constants& constants, int level, int coarser, const PixelPrices& prices);

// Step 2: the selection. A candidate is a level-n pixel with v(q) > τ (or, SPEC §14.2, v(q) >
// (1 − h) τ where `previous` says the previous frame marked it: the marks' hysteresis). Ordered by
// v(q) / price(q), most first (a marked-before candidate's priority divided by 1 − h; a price of 0
// first of all), ties in row-major order, each is taken when it fits what is left of `budgetNs`
// (one that does not is passed over, the next may). `varies` holds the marks (level n's grid).
struct RefinementSelection {
  ImageU8 varies;
  double spentNs = 0.0;     // the predicted cost of what was taken
  int64_t candidates = 0;   // v(q) over its threshold
  int64_t taken = 0;
  int64_t kept = 0;         // of the taken, marked by the previous frame too (SPEC §14.2)
  std::vector<double> prices;  // what it selected with (candidatePrices), kept for compare and probe
};
RefinementSelection selectRefinement(const ImageF& range, const std::vector<double>& prices, double budgetNs, float tau,
                                     float hysteresis, const ImageU8* previous);

}  // namespace mrr
