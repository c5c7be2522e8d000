// mrr-effect beyond the catalogue (SPEC §12.2's separable range, §12.4's budget in predicted time,
// §14's temporal term): each part against its readable rule or a hand-made case, then on frames.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/effect_budget.h"
#include "common/hash.h"
#include "common/shader_constants.h"
#include "common/temporal.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/temporal.h"
#include "scenes/cameras.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

using test::renderScene;
using test::ssaoSettings;

// SPEC §12.2 step 1: the separable range test (rows of three, then columns of three over their
// extremes) gives localRange's bits at every pixel, for any stencil, hit pattern and channel count.
TEST(EffectBudget, SeparableRangeEqualsTheWholeNeighbourhood) {
  for (const int channels : {1, 3})
    for (const auto [w, h] : {std::pair{1, 1}, std::pair{2, 7}, std::pair{37, 23}, std::pair{64, 36}})
      for (int pattern = 0; pattern < 4; ++pattern) {
        ImageF c(w, h, channels);
        ImageU8 stencil(w, h), hit(w, h);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const uint32_t r = pcgHash(static_cast<uint32_t>(x + 1000 * y + 77777 * pattern + 13 * channels));
            stencil.at(x, y) = pattern == 0 ? 1 : (r % 5) != 0;
            hit.at(x, y) = pattern == 3 ? (r >> 7) % 2 : (r >> 9) % 11 != 0;
            for (int k = 0; k < channels; ++k)
              c.at(x, y, k) = static_cast<float>(pcgHash(r + static_cast<uint32_t>(k)) % 100000) * 1e-5f - 0.2f;
          }
        const ImageF whole = localRanges(c, stencil, hit), separable = localRangesSeparable(c, stencil, hit);
        ASSERT_EQ(whole.data, separable.data) << w << "x" << h << " channels " << channels << " pattern " << pattern;
        const ImageU8 a = variesAbove(whole, 0.1f), b = variesAbove(separable, 0.1f);
        ASSERT_EQ(a.data, b.data);
      }
}

// SPEC §12.4 step 2: a candidate's price is the sum of its window's unshaded pixels' prices, the
// window its children widened by r_ℓ and clipped; checked against a direct sum.
TEST(EffectBudget, CandidatePricesSumTheUnshadedWindow) {
  Settings s = ssaoSettings(96, 48);
  s.mode = Mode::MrrEffect;
  const Constants c = makeConstants(s, 1.0f);
  ImageU8 hit(c.paddedWidth, c.paddedHeight);
  for (int y = 0; y < hit.height; ++y)
    for (int x = 0; x < hit.width; ++x) hit.at(x, y) = x + y > 20;
  const UnitPrices prices{5, 7, 1};
  // a coarser level one and two steps away (its windows 2 and 4 level pixels a side, widened)
  for (const auto& [level, coarser] : {std::pair{1, 2}, std::pair{0, 2}, std::pair{0, 1}}) {
    const LevelConstants& fine = c.levels[static_cast<size_t>(level)];
    ImageU8 stencil(fine.width, fine.height);
    for (int y = 0; y < stencil.height; ++y)
      for (int x = 0; x < stencil.width; ++x) stencil.at(x, y) = pcgHash(static_cast<uint32_t>(x * 31 + y)) % 3 == 0;
    const std::vector<uint32_t> got = candidatePrices(stencil, hit, ImageU8(), c, level, coarser, prices);
    const LevelConstants& coarse = c.levels[static_cast<size_t>(coarser)];
    ASSERT_EQ(got.size(), static_cast<size_t>(coarse.width) * static_cast<size_t>(coarse.height));
    const int r = fine.blurRadius, ratio = 1 << (coarser - level);
    ASSERT_GT(r, 0);
    for (int qy = 0; qy < coarse.height; ++qy)
      for (int qx = 0; qx < coarse.width; ++qx) {
        uint32_t expected = 0;
        for (int y = qy * ratio - r; y < (qy + 1) * ratio + r; ++y)
          for (int x = qx * ratio - r; x < (qx + 1) * ratio + r; ++x) {
            if (x < 0 || y < 0 || x >= fine.width || y >= fine.height || stencil.at(x, y)) continue;
            expected += levelPixelHit(hit, x, y, fine.scale) ? prices.paying : prices.leaving;
          }
        ASSERT_EQ(got[static_cast<size_t>(qy * coarse.width + qx)], expected)
            << "level " << level << " from " << coarser << ": " << qx << "," << qy;
      }
  }
}

// SPEC §12.4 step 3: the key from the bits. v = 1 (0x3f800000 >> 20 = 1016) at a price of 1 (log key
// 0) is 1016 + 256; each octave of price is kBudgetKeyBits steps down, each of v up; the hysteresis'
// bonus adds; a free candidate is the top key.
TEST(EffectBudget, PriorityKeysGrowWithVariationPerUnit) {
  EXPECT_EQ(priceKey(1), 0u);
  EXPECT_EQ(priceKey(2), 8u);
  EXPECT_EQ(priceKey(3), 12u);   // 2^1 × 1.5: the mantissa's top bit
  EXPECT_EQ(priceKey(15), 31u);  // 2^3 × 1.875
  EXPECT_EQ(priceKey(1000), 9u * 8u + 7u);  // 2^9 × 1.953
  EXPECT_EQ(priorityKey(1.0f, 1, 0), 1016u + 256u);
  EXPECT_EQ(priorityKey(1.0f, 2, 0), 1016u + 256u - 8u);
  EXPECT_EQ(priorityKey(2.0f, 2, 0), 1016u + 256u);
  EXPECT_EQ(priorityKey(0.5f, 1, 3), 1016u - 8u + 256u + 3u);
  // every v and price lands inside the keys, below the free candidates' top key
  EXPECT_GE(priorityKey(1e-45f, 0xffffffffu, 0), 1u);
  EXPECT_LE(priorityKey(3e38f, 1, 54), static_cast<uint32_t>(kBudgetKeys - 2));
  EXPECT_EQ(priorityKey(0.25f, 0, 0), static_cast<uint32_t>(kBudgetKeys - 1));
  EXPECT_EQ(hysteresisBonus(0.0f), 0u);
  EXPECT_EQ(hysteresisBonus(0.5f), 8u);
  EXPECT_EQ(hysteresisBonus(0.75f), 16u);
  // monotone: more variation never lowers the key, a higher price never raises it
  for (uint32_t price = 1; price < 5000; price += 37) {
    uint32_t last = 0;
    for (float v = 1e-4f; v < 4.0f; v *= 1.13f) {
      const uint32_t k = priorityKey(v, price, 0);
      EXPECT_GE(k, last);
      EXPECT_GE(k, priorityKey(v, price + 1, 0));
      last = k;
    }
  }
}

// SPEC §12.4 step 4: the candidates at or above the least key whose total price fits; a free one
// always; all where all fit.
TEST(EffectBudget, SelectionTakesTheMostVariationPerUnitWithinTheShare) {
  ImageF range(6, 1);
  range.data = {0.5f, 0.2f, 0.9f, 0.05f, 0.3f, 0.4f};
  const std::vector<uint32_t> prices = {10, 1, 30, 0, 4, 0};
  std::vector<uint32_t> key(6);
  for (size_t i = 0; i < 6; ++i) key[i] = priorityKey(range.data[i], prices[i], 0);
  // priorities 0.05, 0.2, 0.03, (free), 0.075, (free): keys in that order
  ASSERT_GT(key[1], key[4]);
  ASSERT_GT(key[4], key[0]);
  ASSERT_GT(key[0], key[2]);
  const auto marks = [](const RefinementSelection& s) { return std::vector<uint8_t>(s.varies.data.begin(), s.varies.data.end()); };
  // τ 0.1 drops pixel 3; a share of 15 takes 1, 4 and 0 (15) and the free 5, not 2
  const RefinementSelection s = selectRefinement(range, prices, 15, 0.1f, 0.0f, nullptr);
  EXPECT_EQ(s.candidates, 5);
  EXPECT_EQ(marks(s), (std::vector<uint8_t>{1, 1, 0, 0, 1, 1}));
  EXPECT_EQ(s.spent, 15u);
  EXPECT_EQ(s.threshold, key[2] + 1);  // the least key whose total fits: one past the first that does not
  // a share of 14: 0 no longer fits, and the threshold rises past it (nothing cheaper below is taken)
  const RefinementSelection t = selectRefinement(range, prices, 14, 0.1f, 0.0f, nullptr);
  EXPECT_EQ(marks(t), (std::vector<uint8_t>{0, 1, 0, 0, 1, 1}));
  EXPECT_EQ(t.spent, 5u);
  // a share of 0: the free ones alone; a share of 45 or more: all
  EXPECT_EQ(marks(selectRefinement(range, prices, 0, 0.0f, 0.0f, nullptr)), (std::vector<uint8_t>{0, 0, 0, 1, 0, 1}));
  const RefinementSelection all = selectRefinement(range, prices, 45, 0.0f, 0.0f, nullptr);
  EXPECT_EQ(all.taken, 6);
  EXPECT_EQ(all.threshold, 0u);
  EXPECT_EQ(all.spent, 45u);
  // SPEC §14.2: marked before, pixel 0 keeps its mark at (1 − h) τ and its bonus puts it above 4
  ImageU8 before(6, 1);
  before.data = {1, 0, 0, 0, 0, 0};
  const RefinementSelection u = selectRefinement(range, prices, 11, 0.1f, 0.9f, &before);
  EXPECT_EQ(marks(u), (std::vector<uint8_t>{1, 1, 0, 0, 0, 1}));
  EXPECT_EQ(u.kept, 1);
  EXPECT_EQ(u.spent, 11u);
  // held at 2^32 − 1: totals past it never fit a share below it
  ImageF two(2, 1);
  two.data = {0.5f, 0.5f};
  const RefinementSelection big = selectRefinement(two, {0xffffffffu, 0xffffffffu}, 0xfffffffeu, 0.0f, 0.0f, nullptr);
  EXPECT_EQ(big.taken, 0);
  EXPECT_EQ(big.threshold, priorityKey(0.5f, 0xffffffffu, 0) + 1);
}

// On a frame: the budgeted term spends no more than the level's share, refines a subset of what τ
// alone refines, and with no budget left refines nothing.
TEST(EffectBudget, BudgetedFramesSpendWithinTheirShare) {
  Settings s = ssaoSettings(160, 96, 16);
  s.mode = Mode::MrrEffect;
  s.effectMask.posterior = 0.02f;
  s.effectMask.budget = 0.0f;  // τ_v alone
  const auto unbudgeted = renderScene("builtin:demo", s);
  for (const float budget : {0.3f, 0.6f, 1.0f}) {
    s.effectMask.budget = budget;
    const auto f = renderScene("builtin:demo", s);
    ASSERT_FALSE(f.frame.fallback.fellBack);
    for (int l = 0; l < kLevelCount; ++l) {
      const RefinementRecord& r = f.frame.refinement[static_cast<size_t>(l)];
      if (!r.budgeted) continue;
      EXPECT_LE(r.spentUnits, r.shareUnits) << "budget " << budget << " level " << l;
      EXPECT_LE(r.taken, r.candidates);
    }
    // the first refined level (2, from the unrefined level 3): the budget's marks are some of τ's
    const ImageU8& a = f.frame.levels[2].marks;
    const ImageU8& b = unbudgeted.frame.levels[2].marks;
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i) ASSERT_LE(a.data[i], b.data[i]) << "budget " << budget;
  }
  // Nothing left after the a-priori stencils: only the free candidates are marked, those whose
  // children and blur reach are shaded already (they move a_l's weights and add no pixel).
  s.effectMask.budget = 1e-6f;
  const auto none = renderScene("builtin:demo", s);
  for (int l = 0; l < kLevelCount; ++l) {
    const RefinementRecord& r = none.frame.refinement[static_cast<size_t>(l)];
    if (!r.budgeted) continue;
    EXPECT_EQ(r.spentUnits, 0u) << "level " << l;
    const ImageU8& marked = none.frame.levels[static_cast<size_t>(l)].marked;
    ASSERT_EQ(marked.data.size(), r.candidatePrices.size());
    int64_t marks = 0;
    for (size_t i = 0; i < marked.data.size(); ++i)
      if (marked.data[i]) {
        EXPECT_EQ(r.candidatePrices[i], 0u) << "level " << l << " candidate " << i;
        ++marks;
      }
    EXPECT_EQ(marks, r.taken) << "level " << l;
  }
}

// SPEC §14.2 on a frame: the second frame of a still camera reads the first one's selection; with
// the hysteresis the candidates the first frame marked need less variation, so there are at least as
// many candidates, and some of those taken were taken before.
TEST(EffectBudget, TheMarksHysteresisKeepsWhatThePreviousFrameSelected) {
  Settings s = ssaoSettings(160, 96, 8);
  s.mode = Mode::MrrEffect;
  s.effectMask.posterior = 0.02f;
  s.effectMask.budget = 0.6f;
  s.effectMask.temporal = 0.5f;  // the history that carries the selection
  s.effectMask.hysteresis = 0.5f;
  auto first = renderScene("builtin:demo", s);
  ASSERT_FALSE(first.frame.fallback.fellBack);
  RenderOptions o;
  o.history = &first.frame.history;
  const FrameResult second = first.renderer->render(first.camera, makeConstants(s, first.framedSize), o);
  int64_t kept = 0;
  for (int l = 0; l < kLevelCount; ++l) {
    const RefinementRecord &a = first.frame.refinement[static_cast<size_t>(l)], &b = second.refinement[static_cast<size_t>(l)];
    if (!b.budgeted) continue;
    EXPECT_EQ(a.kept, 0) << "the first frame has no previous one";
    EXPECT_FALSE(b.previousMarked.empty()) << "level " << l;
    EXPECT_GE(b.candidates, a.candidates) << "level " << l;
    EXPECT_LE(b.kept, b.taken);
    kept += b.kept;
  }
  EXPECT_GT(kept, 0);
  // without the hysteresis the previous selection is not read
  s.effectMask.hysteresis = 0.0f;
  const FrameResult plain = first.renderer->render(first.camera, makeConstants(s, first.framedSize), o);
  for (const RefinementRecord& r : plain.refinement) EXPECT_EQ(r.kept, 0);
}

// SPEC §14: the same camera twice, the history its own previous frame: every pixel the coarser levels
// serve keeps λ (1 − α_0) of a history equal to its own value, so the result is the blend's within
// rounding; a pixel at full resolution (α_0 = 1) and every pixel off geometry are the blend's bit for bit.
TEST(Temporal, AStillCameraKeepsItsOwnImage) {
  Settings s = ssaoSettings(160, 96, 8);
  s.mode = Mode::MrrEffect;
  s.effectMask.temporal = 0.5f;
  auto first = renderScene("builtin:demo", s);
  ASSERT_TRUE(first.frame.temporal.empty());                       // no previous frame: nothing blended
  ASSERT_EQ(first.frame.final().data, first.frame.blend.final.data);  // the blend's bits
  ASSERT_FALSE(first.frame.history.empty());
  RenderOptions o;
  o.history = &first.frame.history;
  const FrameResult second = first.renderer->render(first.camera, makeConstants(s, first.framedSize), o);
  ASSERT_FALSE(second.temporal.empty());
  const Constants& c = second.constants;
  int64_t kept = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const float a0 = levelZeroAlpha(second.levels[0].masks, c.levels[0].weight, x, y);
      const float lambdaP = second.temporal.weight.at(x, y);
      if (!second.levels[0].gbuffer.hit.at(x, y) || a0 == 1.0f) {
        ASSERT_EQ(lambdaP, 0.0f) << x << "," << y;
        ASSERT_EQ(second.final().at(x, y), second.blend.final.at(x, y)) << x << "," << y;
        continue;
      }
      kept += lambdaP > 0.0f;
      if (lambdaP > 0.0f) ASSERT_FLOAT_EQ(lambdaP, 0.5f * (1.0f - a0));
      ASSERT_NEAR(second.final().at(x, y), second.blend.final.at(x, y), 1e-4f) << x << "," << y;
    }
  EXPECT_GT(kept, c.width * c.height / 10) << "a still camera should find its surfaces again";
}

// SPEC §14 step 3: a history whose depths are all elsewhere shows no surface: nothing is kept.
TEST(Temporal, AnotherSurfaceIsNoHistory) {
  Settings s = ssaoSettings(160, 96, 8);
  s.mode = Mode::MrrEffect;
  s.effectMask.temporal = 0.9f;
  auto first = renderScene("builtin:demo", s);
  FrameHistory moved = first.frame.history;
  for (float& z : moved.depth.data)
    if (z > 0.0f) z *= 1.2f;  // 20% deeper than δ = 5% allows
  RenderOptions o;
  o.history = &moved;
  const FrameResult second = first.renderer->render(first.camera, makeConstants(s, first.framedSize), o);
  for (float w : second.temporal.weight.data) ASSERT_EQ(w, 0.0f);
  EXPECT_EQ(second.final().data, second.blend.final.data);
}

// SPEC §14 along a path: the term off (λ = 0) is today's mrr-effect bit for bit; with it, a pixel
// keeps part of the previous frame only where the history has a sample; mrr never reads one.
TEST(Temporal, OffIsTodaysFrameAndMrrNeverReadsAHistory) {
  Settings s = ssaoSettings(128, 72, 8);
  s.mode = Mode::MrrEffect;
  auto base = renderScene("builtin:demo", s);
  const std::vector<Camera> path = cameraPath(base.camera, "orbit", 8);
  FrameHistory history;
  for (int t = 0; t < 3; ++t) {
    Settings on = s;
    on.effectMask.temporal = 0.6f;
    RenderOptions o;
    if (!history.empty()) o.history = &history;
    FrameResult f = base.renderer->render(path[static_cast<size_t>(t)], makeConstants(on, base.framedSize), o);
    const FrameResult off = base.renderer->render(path[static_cast<size_t>(t)], makeConstants(s, base.framedSize), o);
    EXPECT_TRUE(off.temporal.empty());
    EXPECT_TRUE(off.history.empty());
    EXPECT_EQ(off.blend.final.data, f.blend.final.data) << "the blend does not see the term";
    if (t > 0) EXPECT_FALSE(f.temporal.empty());
    history = std::move(f.history);
  }
  Settings mrr = s;
  mrr.mode = Mode::Mrr;
  mrr.effectMask.temporal = 0.6f;  // mrr does not own the parameter: no term
  RenderOptions o;
  o.history = &history;
  const FrameResult m = base.renderer->render(path[3], makeConstants(mrr, base.framedSize), o);
  EXPECT_TRUE(m.temporal.empty());
}

// The term's parts are pure functions of their pixel: the oracle's bits at 1 and 2 threads.
TEST(Temporal, OneAndTwoThreadsGiveIdenticalBits) {
  Settings s = ssaoSettings(128, 72, 8);
  s.mode = Mode::MrrEffect;
  s.effectMask.temporal = 0.6f;
  s.effectMask.posterior = 0.02f;
  s.effectMask.budget = 0.5f;
  auto base = renderScene("builtin:demo", s);
  const std::vector<Camera> path = cameraPath(base.camera, "orbit", 8);
  std::vector<ImageF> results;
  for (const int threads : {1, 2}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    FrameHistory history = base.frame.history;
    RenderOptions o;
    o.history = &history;
    const FrameResult f = base.renderer->render(path[2], makeConstants(s, base.framedSize), o);
    results.push_back(f.final());
  }
  EXPECT_EQ(results[0].data, results[1].data);
}

}  // namespace
}  // namespace mrr
