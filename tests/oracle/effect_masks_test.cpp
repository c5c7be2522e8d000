// mrr-effect (SPEC §12, the oracle's experiment): the footprint widens mrr's masks, never narrows
// them, and with no footprint leaves them exactly as they were.
#include <gtest/gtest.h>

#include "common/error.h"
#include "common/hash.h"
#include "common/kernels.h"
#include "cpu_ref/blend.h"
#include "cpu_ref/effect_masks.h"
#include "cpu_ref/masks.h"
#include "cpu_ref/foveation.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

using test::countSet;
using test::renderScene;
using test::ssaoSettings;

TEST(EffectMasks, DilateByReachIsTheUnionOfSquares) {
  ImageU8 m(20, 12);
  m.at(3, 3) = 1;
  m.at(15, 8) = 1;
  Image<int16_t> k(20, 12, 1, int16_t{-1});
  k.at(3, 3) = 2;   // a 5×5 square, clipped by nothing
  k.at(15, 8) = 4;  // a 9×9 square, clipped by the right and bottom borders
  const ImageU8 d = dilateByReach(m, k);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 20; ++x) {
      const bool a = std::abs(x - 3) <= 2 && std::abs(y - 3) <= 2;
      const bool b = std::abs(x - 15) <= 4 && std::abs(y - 8) <= 4;
      EXPECT_EQ(d.at(x, y), a || b ? 1 : 0) << x << "," << y;
    }
}

TEST(EffectMasks, LevelReachRoundsTheFootprintInLevelPixelsAndCaps) {
  ImageU8 m(4, 1);
  m.data = {1, 1, 1, 0};
  ImageF f(4, 1);
  f.data = {2.9f, 3.1f, 1000.0f, 50.0f};
  const Image<int16_t> k = levelReach(m, f, 2, 8);  // level 1: s = 2
  EXPECT_EQ(k.data[0], 1);   // ⌊1.45 + ½⌋
  EXPECT_EQ(k.data[1], 2);   // ⌊1.55 + ½⌋
  EXPECT_EQ(k.data[2], 8);   // the cap
  EXPECT_EQ(k.data[3], -1);  // no edge: reaches nothing
}

// Every level's stencil of mrr-effect contains mrr's. By default (first widened level 1) level 0
// is mrr's and level 1 grows; widened from level 0, level 0 grows too.
TEST(EffectMasks, ShadesASupersetOfMrrsPixels) {
  Settings s = ssaoSettings(160, 96, 8);
  const auto mrr = renderScene("builtin:demo", s);
  for (const int first : {1, 0}) {
    s.mode = Mode::MrrEffect;
    s.effectMask.budget = 0.0f;  // the a-priori masks (the budget's marks may add level-0 pixels)
    s.effectMask.trim = false;   // the widening alone (§12.5's trim then cuts what the blend never reads)
    s.effectMask.firstLevel = first;
    const auto eff = renderScene("builtin:demo", s);
    ASSERT_FALSE(eff.frame.fallback.fellBack);
    for (int l = 0; l < kLevelCount; ++l) {
      const ImageU8& a = mrr.frame.levels[static_cast<size_t>(l)].masks.stencil;
      const ImageU8& b = eff.frame.levels[static_cast<size_t>(l)].masks.stencil;
      if (a.empty()) continue;
      ASSERT_EQ(a.data.size(), b.data.size());
      for (size_t i = 0; i < a.data.size(); ++i) ASSERT_LE(a.data[i], b.data[i]) << "level " << l << " pixel " << i;
    }
    const int64_t l0 = countSet(mrr.frame.levels[0].masks.stencil), e0 = countSet(eff.frame.levels[0].masks.stencil);
    if (first == 0) EXPECT_GT(e0, l0);
    else EXPECT_EQ(e0, l0);
    EXPECT_GT(countSet(eff.frame.levels[1].masks.stencil), countSet(mrr.frame.levels[1].masks.stencil)) << "first " << first;
  }
}

// SPEC §12.2, the a-posteriori term: its stencils contain the a priori ones at every level and
// shade more; a τ above any range (AO lies in [0, 1]) is mrr-effect bit for bit; with a gaze
// (§13), no level-0 pixel the limit clears is marked back (without the limit on the marks, the
// demo at ppd 150 gets marks at 62,12 where the limit is 1).
TEST(EffectMasks, APosterioriTermRefinesAndKeepsTheLevelLimit) {
  Settings s = ssaoSettings(160, 96, 8);
  s.mode = Mode::MrrEffect;
  s.neverSlower = false;
  s.effectMask.budget = 0.0f;  // τ_v alone (SPEC §12.2; §12.4's budget is tested apart)
  const auto prior = renderScene("builtin:demo", s);
  s.effectMask.posterior = 2.0f;  // no 3×3 range of AO exceeds it
  const auto none = renderScene("builtin:demo", s);
  EXPECT_EQ(none.frame.blend.final.data, prior.frame.blend.final.data);
  s.effectMask.posterior = 0.05f;
  const auto post = renderScene("builtin:demo", s);
  for (int l = 0; l < kLevelCount; ++l) {
    const ImageU8& a = prior.frame.levels[static_cast<size_t>(l)].masks.stencil;
    const ImageU8& b = post.frame.levels[static_cast<size_t>(l)].masks.stencil;
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i) ASSERT_LE(a.data[i], b.data[i]) << "level " << l << " pixel " << i;
  }
  EXPECT_GT(post.frame.shadedPixelsTotal, prior.frame.shadedPixelsTotal);
  // With a gaze at a corner and a high ppd, the periphery's level 0 is cleared; the term marks none of it back.
  s.foveation.gaze = true;
  s.foveation.gazeX = 0;
  s.foveation.gazeY = 0;
  s.foveation.ppd = 150.0f;  // level 1 allowed from 40 px out: most of the frame
  const auto foveated = renderScene("builtin:demo", s);
  const ImageU8& limit = foveated.frame.levelLimit;
  ASSERT_FALSE(limit.empty());
  const ImageU8& m0 = foveated.frame.levels[0].masks.mask;
  int64_t limited = 0;
  for (int y = 0; y < m0.height; ++y)
    for (int x = 0; x < m0.width; ++x)
      if (limit.at(x, y, kLimitLevel) > 0) {
        ++limited;
        ASSERT_EQ(m0.at(x, y), 0) << "a posteriori mark at " << x << "," << y << " where the limit is "
                                  << int(limit.at(x, y, kLimitLevel));
      }
  EXPECT_GT(limited, 0) << "the gaze limited nothing";
}

// SPEC §12.2 step 2's fast path (blur again only where a new mask bit reaches) gives the readable
// rule's bits: masks and marks of every density, bits at the borders, kernels wider than the level.
TEST(EffectMasks, RefineMasksFastPathMatchesTheReference) {

  for (const float sigma2 : {0.0f, 1.0f, 4.0f, 16.0f, 64.0f})
    for (const auto [w, h] : {std::pair{37, 23}, std::pair{96, 54}, std::pair{9, 70}})
      for (int pattern = 0; pattern < 6; ++pattern) {
        LevelConstants lc;
        lc.gaussian = gaussianWeights(sigma2);
        ImageU8 mask(w, h), marks(w, h);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const uint32_t r = pcgHash(static_cast<uint32_t>(x + w * y + 7919 * pattern));
            mask.at(x, y) = r % 23 == 0;
            switch (pattern) {
              case 0: break;                                                     // no marks
              case 1: marks.at(x, y) = r % 97 == 0; break;                       // sparse
              case 2: marks.at(x, y) = (r >> 8) % 3 == 0; break;                 // dense
              case 3: marks.at(x, y) = x == 0 || y == h - 1; break;              // the borders
              case 4: marks.at(x, y) = (x == w - 1 && y == 0) || (x == w / 2 && y == h / 2); break;
              case 5: marks.at(x, y) = mask.at(x, y); break;                     // nothing new
            }
          }
        MaskLevel fast;
        fast.mask = mask;
        fast.alpha = blurMask(mask, lc.gaussian);
        fast.stencil = ImageU8(w, h);
        for (size_t i = 0; i < fast.alpha.data.size(); ++i) fast.stencil.data[i] = fast.alpha.data[i] > 0.0f;
        fast.stencil.at(0, 0) = 1;  // a bit the closure gave: both keep it
        MaskLevel reference = fast;
        refineMasks(fast, marks, lc);
        refineMasksReference(reference, marks, lc);
        ASSERT_EQ(fast.mask.data, reference.mask.data) << "sigma2 " << sigma2 << " pattern " << pattern;
        ASSERT_EQ(fast.alpha.data, reference.alpha.data) << "sigma2 " << sigma2 << " " << w << "x" << h << " pattern " << pattern;
        ASSERT_EQ(fast.stencil.data, reference.stencil.data) << "sigma2 " << sigma2 << " pattern " << pattern;
      }
}

// With no footprint (scale 0, or an AO radius under half a pixel everywhere), mrr-effect's
// masks, alphas and stencils are mrr's, bit for bit.
TEST(EffectMasks, NoFootprintIsMrrExactly) {
  for (const bool tinyRadius : {false, true}) {
    Settings s = ssaoSettings(160, 96, 8);
    if (tinyRadius) s.ssao.radius = 1e-6f;
    const auto mrr = renderScene("builtin:demo", s);
    s.mode = Mode::MrrEffect;
    s.effectMask.budget = 0.0f;  // the a-priori masks alone
    s.effectMask.trim = false;   // and not §12.5's trim, which cuts mrr's closure too
    if (!tinyRadius) s.effectMask.scale = 0.0f;
    s.effectMask.firstLevel = 0;  // every level could widen
    const auto eff = renderScene("builtin:demo", s);
    for (int l = 0; l < kLevelCount; ++l) {
      const MaskLevel& a = mrr.frame.levels[static_cast<size_t>(l)].masks;
      const MaskLevel& b = eff.frame.levels[static_cast<size_t>(l)].masks;
      EXPECT_EQ(a.stencil.data, b.stencil.data) << "level " << l << (tinyRadius ? " tiny R" : " scale 0");
      EXPECT_EQ(a.alpha.data, b.alpha.data) << "level " << l;
    }
    EXPECT_EQ(mrr.frame.blend.final.data, eff.frame.blend.final.data);
  }
}


// ---- SPEC §12.5: the trim ---------------------------------------------------------------------

// blendReads (separable) is blendReadsReference (the window of every level pixel, read pixel by
// pixel) bit for bit: odd frames whose padded grid is wider than W×H, every level, margin 0 and
// SSAO's 2, reaches sparse, dense and on the borders.
TEST(EffectTrim, ReadsFastPathMatchesTheReference) {
  for (const auto [w, h] : {std::pair{97, 61}, std::pair{64, 40}, std::pair{13, 9}})
    for (int pattern = 0; pattern < 4; ++pattern) {
      Settings s = ssaoSettings(w, h, 4, Mode::MrrEffect);
      const Constants c = makeConstants(s, 1.0f);
      ImageU8 reach(c.levels[0].width, c.levels[0].height, 1, 0);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
          const uint32_t r = pcgHash(static_cast<uint32_t>(x + 977 * y + 7919 * pattern));
          switch (pattern) {
            case 0: reach.at(x, y) = static_cast<uint8_t>(r % 101 == 0 ? 1 + r % 3 : 0); break;  // sparse
            case 1: reach.at(x, y) = static_cast<uint8_t>(r % 4); break;                         // dense
            case 2: reach.at(x, y) = static_cast<uint8_t>(x == c.width - 1 || y == 0 ? 3 : 0); break;
            case 3: reach.at(x, y) = static_cast<uint8_t>(x == 0 && y == c.height - 1 ? 3 : 0); break;
          }
        }
      for (int l = 1; l < kLevelCount; ++l)
        for (const int margin : {0, 2}) {
          const ImageU8 fast = blendReads(reach, l, margin, c), reference = blendReadsReference(reach, l, margin, c);
          ASSERT_EQ(fast.data, reference.data) << w << "x" << h << " pattern " << pattern << " level " << l << " margin " << margin;
          if (pattern == 1) EXPECT_GT(test::countSet(fast), 0);
        }
    }
}

// R(p), blendReach on a frame's masks, is where the blend stops: the finest level whose α_ℓ (the
// blend's own stage image) is 1, else the coarsest; the same on the trimmed and the untrimmed
// masks (a pixel keeps the taps of every level it reads).
TEST(EffectTrim, ReachIsTheBlendsFirstOpaqueLevel) {
  for (const Effect effect : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
    Settings s = defaultSettings(effect);
    s.width = 97;
    s.height = 61;
    s.mode = Mode::MrrEffect;
    s.neverSlower = false;
    s.effectMask.budget = 0.0f;  // the a-priori masks
    ImageU8 reaches[2];
    for (const bool trim : {false, true}) {
      s.effectMask.trim = trim;
      const auto r = renderScene(effect == Effect::Ssm ? "builtin:shadows" : "builtin:demo", s);
      const FrameResult& f = r.frame;
      const Constants& c = f.constants;
      std::array<LevelImages, kLevelCount> in;
      for (size_t l = 0; l < kLevelCount; ++l) in[l] = {nullptr, &f.levels[l].masks.stencil, &f.levels[l].masks.alpha};
      const ImageU8 reach = blendReach(in, c);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
          int expected = c.coarsestEnabled;
          for (int l = 0; l < c.coarsestEnabled; ++l)
            if (c.levels[static_cast<size_t>(l)].enabled && f.blend.alpha[static_cast<size_t>(l)].at(x, y) == 1.0f) {
              expected = l;
              break;
            }
          ASSERT_EQ(reach.at(x, y), expected) << toString(effect) << (trim ? " trimmed" : "") << " at " << x << "," << y;
        }
      reaches[trim ? 1 : 0] = reach;
    }
    EXPECT_EQ(reaches[0].data, reaches[1].data) << toString(effect);
  }
}

// Without the a-posteriori term the trim changes nothing the blend shows: the final image and
// level map are the untrimmed frame's bit for bit (fast and stepwise blend alike), each level's
// S_ℓ ⊆ the untrimmed one's and ⊆ D_ℓ, and fewer pixels are shaded (not vacuous). With the budget's
// refinement the trimmed levels keep S_ℓ ⊆ D_ℓ.
TEST(EffectTrim, KeepsTheFinalImageBitForBitAndShadesLess) {
  for (const Effect effect : {Effect::Ssao, Effect::Ssm, Effect::Ssgi})
    for (const bool keepStages : {true, false}) {
      Settings s = defaultSettings(effect);
      s.width = 160;
      s.height = 90;
      s.mode = Mode::MrrEffect;
      s.neverSlower = false;
      s.effectMask.budget = 0.0f;
      const std::string scene = effect == Effect::Ssm ? "builtin:shadows" : "builtin:demo";
      s.effectMask.trim = false;
      const auto whole = renderScene(scene, s);
      s.effectMask.trim = true;
      const test::Rendered trimmed = [&] {
        test::Rendered r = renderScene(scene, s);
        if (!keepStages) r.frame = r.renderer->render(r.camera, r.frame.constants, {false});
        return r;
      }();
      const std::string what = toString(effect) + (keepStages ? "" : " (final-only blend)");
      EXPECT_EQ(trimmed.frame.blend.final.data, whole.frame.blend.final.data) << what;
      EXPECT_EQ(trimmed.frame.blend.levelMap.data, whole.frame.blend.levelMap.data) << what;
      EXPECT_LT(trimmed.frame.shadedPixelsTotal, whole.frame.shadedPixelsTotal) << what << ": the trim cut nothing";
      EXPECT_TRUE(trimmed.frame.levels[0].masks.read.empty()) << "level 0 is never trimmed";
      for (int l = 1; l < kLevelCount; ++l) {
        const MaskLevel& t = trimmed.frame.levels[static_cast<size_t>(l)].masks;
        const MaskLevel& u = whole.frame.levels[static_cast<size_t>(l)].masks;
        if (t.stencil.empty()) continue;
        ASSERT_EQ(t.read.data.size(), t.stencil.data.size()) << what << " level " << l;
        for (size_t i = 0; i < t.stencil.data.size(); ++i)
          ASSERT_TRUE(!t.stencil.data[i] || (u.stencil.data[i] && t.read.data[i])) << what << " level " << l << " pixel " << i;
      }
      s.effectMask.budget = 0.85f;  // the default: refined levels keep the trim
      const auto refined = renderScene(scene, s);
      for (int l = 1; l < kLevelCount; ++l) {
        const MaskLevel& t = refined.frame.levels[static_cast<size_t>(l)].masks;
        if (t.stencil.empty()) continue;
        for (size_t i = 0; i < t.stencil.data.size(); ++i)
          ASSERT_TRUE(!t.stencil.data[i] || t.read.data[i]) << what << " refined level " << l << " pixel " << i;
      }
    }
}

}  // namespace
}  // namespace mrr
