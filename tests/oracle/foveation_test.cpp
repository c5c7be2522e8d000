// Foveation and motion (SPEC §13): the eccentricity and the level thresholds against the formula,
// the limit only ever clears masks, the fovea and a still camera keep mrr's frame bit for bit.
#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "cpu_ref/foveation.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

using test::countSet;
using test::renderScene;
using test::ssaoSettings;

Constants::Foveation gazeAt(int x, int y, float ppd) {
  FoveationSettings s;
  s.gaze = true;
  s.gazeX = x;
  s.gazeY = y;
  s.ppd = ppd;
  Constants::Foveation f;
  makeFoveationConstants(s, f);
  return f;
}

TEST(Foveation, EccentricityIsTheDistanceToTheGazeOverPpd) {
  const Constants::Foveation f = gazeAt(100, 50, 30.0f);
  EXPECT_EQ(eccentricityAt(100, 50, f), 0.0f);
  EXPECT_FLOAT_EQ(eccentricityAt(130, 90, f), 50.0f / 30.0f);  // a 30-40-50 triangle
  EXPECT_FLOAT_EQ(eccentricityAt(40, 50, f), 2.0f);
  EXPECT_EQ(eccentricityAt(5, 5, Constants::Foveation{}), 0.0f);  // no gaze: the fovea everywhere
}

// Level ℓ starts where a level pixel, s_ℓ/ppd degrees, is half Guenter's ω(e) = m e + ω0:
// e_ℓ = (2 s_ℓ/ppd − ω0)/m, i.e. r_ℓ = e_ℓ·ppd pixels from the gaze. Checked along a row, on
// both sides of each threshold, for two viewing conditions; the level never falls going out.
TEST(Foveation, LevelStartsWhereAPixelIsHalfTheMinimumAngleOfResolution) {
  for (const float ppd : {30.0f, 67.0f}) {
    const Constants::Foveation f = gazeAt(0, 0, ppd);
    EXPECT_DOUBLE_EQ(f.mar0, 1.0 / 48.0);
    EXPECT_DOUBLE_EQ(f.marSlope, 0.022);
    int previous = 0;
    for (int x = 0; x < 4000; ++x) {
      const int level = foveationLevel(x, 0, f);
      EXPECT_GE(level, previous) << x;
      previous = level;
      int expected = 0;
      for (int l = 1; l < kLevelCount; ++l) {
        const double r = (2.0 * (1 << l) / ppd - 1.0 / 48.0) / (1.32 / 60.0) * ppd;
        if (x >= r) expected = l;
      }
      ASSERT_EQ(level, expected) << "ppd " << ppd << " x " << x;
    }
    EXPECT_EQ(previous, kLevelCount - 1);
  }
  // ppd 30: level 1 from 153.4 px (5.11 degrees), level 2 from 335.2 px, level 3 from 698.9 px.
  const Constants::Foveation f = gazeAt(0, 0, 30.0f);
  EXPECT_EQ(foveationLevel(153, 0, f), 0);
  EXPECT_EQ(foveationLevel(154, 0, f), 1);
  EXPECT_EQ(foveationLevel(335, 0, f), 1);
  EXPECT_EQ(foveationLevel(336, 0, f), 2);
}

TEST(Foveation, MotionLevelFollowsTheBlurWidthAndIsCapped) {
  FoveationSettings s;
  s.motion = true;
  Constants::Foveation f;
  makeFoveationConstants(s, f);
  EXPECT_EQ(motionLevel({3.99f, 0.0f}, f), 0);
  EXPECT_EQ(motionLevel({4.0f, 0.0f}, f), 1);   // a blur 4 pixels wide holds two level-1 pixels
  EXPECT_EQ(motionLevel({0.0f, 7.9f}, f), 1);
  EXPECT_EQ(motionLevel({6.0f, 6.0f}, f), 2);   // |v| = 8.49
  EXPECT_EQ(motionLevel({100.0f, 0.0f}, f), 2); // the cap: motion alone never asks for level 3
  EXPECT_EQ(motionLevel({kMotionBehind, kMotionBehind}, f), 2);
  s.motionCap = 3;
  makeFoveationConstants(s, f);
  EXPECT_EQ(motionLevel({100.0f, 0.0f}, f), 3);
}

TEST(Foveation, BadViewingConditionsAreRefused) {
  Settings s = ssaoSettings(64, 32);
  s.foveation.ppd = 0.0f;
  EXPECT_THROW(validateSettings(s), MrrError);
  s.foveation.ppd = -3.0f;
  EXPECT_THROW(validateSettings(s), MrrError);
  s.foveation.ppd = 30.0f;
  s.foveation.gaze = true;
  s.foveation.gazeX = 64;  // one past the last column
  EXPECT_THROW(validateSettings(s), MrrError);
  s.foveation.gazeX = 63;
  s.foveation.gazeY = -1;
  EXPECT_THROW(validateSettings(s), MrrError);
  s.foveation.gazeY = 31;
  EXPECT_NO_THROW(validateSettings(s));
}

void expectSameFrame(const FrameResult& a, const FrameResult& b) {
  for (int l = 0; l < kLevelCount; ++l) {
    const MaskLevel& x = a.levels[static_cast<size_t>(l)].masks;
    const MaskLevel& y = b.levels[static_cast<size_t>(l)].masks;
    EXPECT_EQ(x.mask.data, y.mask.data) << "M level " << l;
    EXPECT_EQ(x.alpha.data, y.alpha.data) << "a level " << l;
    EXPECT_EQ(x.stencil.data, y.stencil.data) << "S level " << l;
  }
  EXPECT_EQ(a.final().data, b.final().data);
  EXPECT_EQ(a.shaded.data, b.shaded.data);
}

// A frame wholly inside the fovea (ppd 5: level 1 starts 181 px out, the 160×96 frame's corners
// are 93 px from its centre) and a previous frame with the same camera are mrr's bit for bit.
TEST(Foveation, FoveaAndStillCameraAreMrrBitForBit) {
  Settings s = ssaoSettings(160, 96, 8);
  const auto mrr = renderScene("builtin:demo", s);
  Settings g = s;
  g.foveation.gaze = true;
  g.foveation.gazeX = 80;
  g.foveation.gazeY = 48;
  g.foveation.ppd = 5.0f;
  const auto fov = renderScene("builtin:demo", g);
  ASSERT_FALSE(fov.frame.levelLimit.empty());
  for (size_t i = 0; i < fov.frame.levelLimit.data.size(); ++i) ASSERT_EQ(fov.frame.levelLimit.data[i], 0) << i;
  expectSameFrame(mrr.frame, fov.frame);

  Settings m = s;
  m.foveation.motion = true;
  m.foveation.prevEye = mrr.camera.eye;
  m.foveation.prevTarget = mrr.camera.target;
  m.foveation.prevUp = mrr.camera.up;
  m.foveation.prevYfov = mrr.camera.yfov;
  const auto still = renderScene("builtin:demo", m);
  ASSERT_FALSE(still.frame.motion.empty());
  float most = 0.0f;
  for (float v : still.frame.motion.data) most = std::max(most, v);
  EXPECT_LT(most, 0.01f) << "a still camera: every surface point projects back onto its own pixel";
  expectSameFrame(mrr.frame, still.frame);
}

// The limit only clears masks: every level's stencil is a subset of mrr's. With the gaze at the
// centre (ppd 30), the periphery coarsens, and inside the fovea (well within 153 px) the final
// image is mrr's bit for bit; the blend and blur reach a few pixels, so 24 px are left as margin.
TEST(Foveation, PeripheryCoarsensFoveaKeepsMrrsImage) {
  Settings s = ssaoSettings(480, 288, 8);
  const auto mrr = renderScene("builtin:demo", s);
  s.foveation.gaze = true;
  s.foveation.gazeX = 240;
  s.foveation.gazeY = 144;
  s.foveation.ppd = 30.0f;
  const auto fov = renderScene("builtin:demo", s);
  ASSERT_FALSE(fov.frame.fallback.fellBack);
  for (int l = 0; l < kLevelCount; ++l) {
    const ImageU8& a = mrr.frame.levels[static_cast<size_t>(l)].masks.stencil;
    const ImageU8& b = fov.frame.levels[static_cast<size_t>(l)].masks.stencil;
    ASSERT_EQ(a.data.size(), b.data.size());
    for (size_t i = 0; i < a.data.size(); ++i) ASSERT_LE(b.data[i], a.data[i]) << "level " << l << " pixel " << i;
  }
  EXPECT_LT(countSet(fov.frame.levels[0].masks.stencil), countSet(mrr.frame.levels[0].masks.stencil));
  int64_t inside = 0, equal = 0;
  const ImageF& a = mrr.frame.final();
  const ImageF& b = fov.frame.final();
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const double d = std::hypot(x - 240.0, y - 144.0);
      if (d < 153.0 - 24.0) {
        ++inside;
        equal += a.at(x, y) == b.at(x, y);
      }
    }
  EXPECT_GT(inside, 40000);
  EXPECT_EQ(equal, inside);
  // Every level-0 pixel past the threshold has M_0 = 0.
  for (int y = 0; y < fov.frame.levels[0].masks.mask.height; ++y)
    for (int x = 0; x < fov.frame.levels[0].masks.mask.width; ++x)
      if ((x - 240) * (x - 240) + (y - 144) * (y - 144) >= fov.frame.constants.foveation.radius2[1]) {
        ASSERT_EQ(fov.frame.levels[0].masks.mask.at(x, y), 0) << x << "," << y;
      }
}

// Tiles (SPEC §9) take max(content rate, the limit at the tile's centre, at most 2).
TEST(Foveation, TilesTakeTheCoarserOfContentAndFoveationRates) {
  Settings s = ssaoSettings(480, 288, 8, Mode::Tiles);
  const auto tiles = renderScene("builtin:demo", s);
  s.foveation.gaze = true;
  s.foveation.gazeX = 0;
  s.foveation.gazeY = 0;
  s.foveation.ppd = 30.0f;
  const auto fov = renderScene("builtin:demo", s);
  const ImageU8& a = tiles.frame.tileRates;
  const ImageU8& b = fov.frame.tileRates;
  ASSERT_EQ(a.data.size(), b.data.size());
  for (int ty = 0; ty < a.height; ++ty)
    for (int tx = 0; tx < a.width; ++tx) {
      const int limit = std::min(2, foveationLevel(std::min(tx * 16 + 8, 479), std::min(ty * 16 + 8, 287),
                                                   fov.frame.constants.foveation));
      EXPECT_EQ(b.at(tx, ty), std::max<int>(a.at(tx, ty), limit)) << tx << "," << ty;
    }
}

// A camera that pans: the points that move by 4 px or more lose level 0, by 8 px level 1 too.
TEST(Foveation, APanningCameraCoarsensWhatMoves) {
  Settings s = ssaoSettings(320, 192, 8);
  const auto mrr = renderScene("builtin:demo", s);
  const glm::vec3 side = glm::normalize(glm::cross(mrr.camera.target - mrr.camera.eye, mrr.camera.up));
  const float step = 0.02f * glm::length(mrr.camera.target - mrr.camera.eye);
  s.foveation.motion = true;
  s.foveation.prevEye = mrr.camera.eye + step * side;
  s.foveation.prevTarget = mrr.camera.target + step * side;
  s.foveation.prevUp = mrr.camera.up;
  s.foveation.prevYfov = mrr.camera.yfov;
  const auto moved = renderScene("builtin:demo", s);
  const FrameResult& f = moved.frame;
  int64_t coarsened = 0;
  for (int y = 0; y < 192; ++y)
    for (int x = 0; x < 320; ++x) {
      const float v = f.motion.at(x, y);
      const int l = f.levelLimit.at(x, y, kLimitMotion);
      ASSERT_EQ(l, v >= 8.0f ? 2 : v >= 4.0f ? 1 : 0) << x << "," << y << " v " << v;
      coarsened += l > 0;
    }
  EXPECT_GT(coarsened, 1000);
  EXPECT_LT(countSet(f.levels[0].masks.stencil), countSet(mrr.frame.levels[0].masks.stencil));
}

// --pan X (motion without a file): the previous view is this one with its eye moved by −X along
// its right axis. A point at view depth z then moves by focal·X/z pixels along the row: the
// screen shift of a translating pinhole camera. And the same motion as a previous frame written
// as that camera (the --prev-frame way), within float rounding.
TEST(Foveation, APanMovesEachPointByFocalTimesPanOverDepth) {
  Settings s = ssaoSettings(320, 192, 8);
  const auto still = renderScene("builtin:demo", s);
  const float pan = 0.02f * glm::length(still.camera.target - still.camera.eye);
  s.foveation.motion = true;
  s.foveation.panned = true;
  s.foveation.pan = pan;
  const auto panned = renderScene("builtin:demo", s);
  const FrameResult& f = panned.frame;
  ASSERT_FALSE(f.motion.empty());
  const View& view = f.view;
  s.foveation.panned = false;
  s.foveation.prevEye = still.camera.eye - pan * view.right;
  s.foveation.prevTarget = still.camera.target - pan * view.right;
  s.foveation.prevUp = still.camera.up;
  s.foveation.prevYfov = still.camera.yfov;
  const auto fromFile = renderScene("builtin:demo", s);
  const GBuffer& g = f.levels[0].gbuffer;
  int64_t onGeometry = 0, coarsened = 0;
  for (int y = 0; y < 192; ++y)
    for (int x = 0; x < 320; ++x) {
      if (!g.hit.at(x, y)) {
        ASSERT_EQ(f.motion.at(x, y), 0.0f) << x << "," << y << ": the background does not move";
        continue;
      }
      const float z = -g.positionAt(x, y).z;
      const float expected = view.focal * pan / z;
      ASSERT_NEAR(f.motion.at(x, y), expected, 1e-3f + 1e-4f * expected) << x << "," << y;
      ASSERT_NEAR(f.motion.at(x, y), fromFile.frame.motion.at(x, y), 1e-3f + 1e-4f * expected) << x << "," << y;
      ++onGeometry;
      coarsened += f.levelLimit.at(x, y, kLimitMotion) > 0;
    }
  EXPECT_GT(onGeometry, 10000);
  EXPECT_GT(coarsened, 1000) << "the pan is large enough to coarsen";
  EXPECT_LT(countSet(f.levels[0].masks.stencil), countSet(still.frame.levels[0].masks.stencil));
  // The other way: the same |v| up to float rounding (SPEC §13's levels read |v| only), so the same
  // level limit but at a pixel whose |v| sits on a threshold.
  s.foveation.panned = true;
  s.foveation.pan = -pan;
  const auto left = renderScene("builtin:demo", s);
  ASSERT_EQ(left.frame.levelLimit.data.size(), f.levelLimit.data.size());
  int64_t differ = 0;
  for (size_t i = 0; i < f.levelLimit.data.size(); ++i) differ += left.frame.levelLimit.data[i] != f.levelLimit.data[i];
  EXPECT_LE(differ, 64);
}

}  // namespace
}  // namespace mrr
