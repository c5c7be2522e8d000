// mrr-effect beyond the catalogue (SPEC §12.2's separable range, §12.4's budget in predicted time,
// §14's temporal term): each part against its readable rule or a hand-made case, then on frames.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/effect_budget.h"
#include "common/hash.h"
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

// SPEC §12.4 step 1: a candidate's price is the sum of its window's unshaded pixels' prices, the
// window its children widened by r_ℓ and clipped; checked against a direct sum.
TEST(EffectBudget, CandidatePricesSumTheUnshadedWindow) {
  Settings s = ssaoSettings(96, 48);
  s.mode = Mode::MrrEffect;
  const Constants c = makeConstants(s, 1.0f);
  ImageU8 hit(c.paddedWidth, c.paddedHeight);
  for (int y = 0; y < hit.height; ++y)
    for (int x = 0; x < hit.width; ++x) hit.at(x, y) = x + y > 20;
  const PixelPrices prices{5.0, 7.0, 1.0};
  // a coarser level one and two steps away (its windows 2 and 4 level pixels a side, widened)
  for (const auto& [level, coarser] : {std::pair{1, 2}, std::pair{0, 2}, std::pair{0, 1}}) {
    const LevelConstants& fine = c.levels[static_cast<size_t>(level)];
    ImageU8 stencil(fine.width, fine.height);
    for (int y = 0; y < stencil.height; ++y)
      for (int x = 0; x < stencil.width; ++x) stencil.at(x, y) = pcgHash(static_cast<uint32_t>(x * 31 + y)) % 3 == 0;
    const std::vector<double> got = candidatePrices(stencil, hit, ImageU8(), c, level, coarser, prices);
    const LevelConstants& coarse = c.levels[static_cast<size_t>(coarser)];
    ASSERT_EQ(got.size(), static_cast<size_t>(coarse.width) * static_cast<size_t>(coarse.height));
    const int r = fine.blurRadius, ratio = 1 << (coarser - level);
    ASSERT_GT(r, 0);
    for (int qy = 0; qy < coarse.height; ++qy)
      for (int qx = 0; qx < coarse.width; ++qx) {
        double expected = 0.0;
        for (int y = qy * ratio - r; y < (qy + 1) * ratio + r; ++y)
          for (int x = qx * ratio - r; x < (qx + 1) * ratio + r; ++x) {
            if (x < 0 || y < 0 || x >= fine.width || y >= fine.height || stencil.at(x, y)) continue;
            expected += levelPixelHit(hit, x, y, fine.scale) ? prices.paying : prices.leaving;
          }
        ASSERT_NEAR(got[static_cast<size_t>(qy * coarse.width + qx)], expected, 1e-9)
            << "level " << level << " from " << coarser << ": " << qx << "," << qy;
      }
  }
}

// SPEC §12.4 step 2: the most variation per nanosecond first, a free candidate first of all, each
// taken while it fits; one that does not fit is passed over.
TEST(EffectBudget, SelectionTakesTheMostVariationPerNanosecondWithinTheBudget) {
  ImageF range(5, 1);
  range.data = {0.5f, 0.2f, 0.9f, 0.05f, 0.3f};
  const std::vector<double> prices = {10.0, 1.0, 30.0, 0.0, 4.0};  // priorities 0.05, 0.2, 0.03, inf, 0.075
  const RefinementSelection s = selectRefinement(range, prices, 15.0, 0.1f, 0.0f, nullptr);
  // τ 0.1 drops pixel 3 (0.05); then 1 (0.2), 4 (0.075), 0 (0.05): 1 + 4 + 10 = 15 fits; 2 does not
  EXPECT_EQ(s.candidates, 4);
  EXPECT_EQ(std::vector<uint8_t>(s.varies.data.begin(), s.varies.data.end()), (std::vector<uint8_t>{1, 1, 0, 0, 1}));
  EXPECT_DOUBLE_EQ(s.spentNs, 15.0);
  // τ 0: the free one first; a budget of 5 takes it, 1 and 4
  const RefinementSelection t = selectRefinement(range, prices, 5.0, 0.0f, 0.0f, nullptr);
  EXPECT_EQ(std::vector<uint8_t>(t.varies.data.begin(), t.varies.data.end()), (std::vector<uint8_t>{0, 1, 0, 1, 1}));
  // SPEC §14.2: marked before, pixel 0 keeps its mark at (1 − h) τ and its priority / (1 − h) puts it first
  ImageU8 before(5, 1);
  before.data = {1, 0, 0, 0, 0};
  const RefinementSelection u = selectRefinement(range, prices, 10.0, 0.1f, 0.9f, &before);
  EXPECT_EQ(u.varies.data[0], 1);
  EXPECT_EQ(u.kept, 1);
  EXPECT_LE(u.spentNs, 10.0);
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
      EXPECT_LE(r.spentNs, r.budgetNs + 1e-6) << "budget " << budget << " level " << l;
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
    EXPECT_EQ(r.spentNs, 0.0) << "level " << l;
    const ImageU8& marked = none.frame.levels[static_cast<size_t>(l)].marked;
    ASSERT_EQ(marked.data.size(), r.candidatePrices.size());
    int64_t marks = 0;
    for (size_t i = 0; i < marked.data.size(); ++i)
      if (marked.data[i]) {
        EXPECT_EQ(r.candidatePrices[i], 0.0) << "level " << l << " candidate " << i;
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
