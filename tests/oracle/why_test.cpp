// SPEC §12.3: probe says why each level covers a pixel — an edge (geometry), the effect's
// footprint (effect), the a-posteriori marks, the closure, or why not (the level limit) — and the
// ablation's effect-only arm shades exactly the pixels the widening adds.
#include <gtest/gtest.h>

#include <cmath>

#include "cpu_ref/masks.h"
#include "cpu_ref/probe.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

using test::renderScene;
using test::ssaoSettings;

std::string reasonAt(const nlohmann::json& probe, int level) {
  return probe["levels"][static_cast<size_t>(level)]["why"]["reason"].get<std::string>();
}

// On the demo at 160×96, mrr-effect SSAO. A full-res edge pixel's level 1 is covered for its edge;
// a level-1 pixel farther from every edge block than the blur reaches, but within the reach that
// R · f / z gives the nearest edge block (computed here by hand from the G-buffer), is covered
// for the effect. Every level's reasons agree with the frame's own stencil, and mrr's geometry
// pixels are mrr-effect's.
TEST(CoverageWhy, AnEdgeIsGeometryAndAPixelWithinReachIsTheEffect) {
  Settings s = ssaoSettings(160, 96, 8);
  const auto mrr = renderScene("builtin:demo", s);
  s.mode = Mode::MrrEffect;
  s.effectMask.budget = 0.0f;  // the a-priori arms alone (the marks: TheLevelLimitAndTheMarks)
  const auto eff = renderScene("builtin:demo", s);
  const FrameResult& f = eff.frame;
  const Constants& c = f.constants;
  ASSERT_FALSE(f.fallback.fellBack);
  const ImageU8& e = f.edges.combined;

  // 1. next to an edge: geometry at level 1 (the block holds an edge), whatever the footprint
  int edgePixels = 0;
  for (int y = 0; y < c.height && edgePixels < 20; y += 3)
    for (int x = 0; x < c.width && edgePixels < 20; x += 3)
      if (e.at(x, y)) {
        const nlohmann::json p = probePixel(f, x, y);
        EXPECT_EQ(reasonAt(p, 1), "geometry") << x << "," << y;
        EXPECT_EQ(p["levels"][1]["why"]["M_geometry"], 1);
        ++edgePixels;
      }
  ASSERT_GT(edgePixels, 0);

  // 2. within reach, out of the blur: the effect. M_1 and K_1 by hand.
  const int lw = c.levels[1].width, lh = c.levels[1].height;
  const int r = static_cast<int>(c.levels[1].gaussian.size() / 2);
  ImageU8 m1(lw, lh);
  Image<int16_t> k1(lw, lh, 1, int16_t{-1});
  const GBuffer& g = f.levels[0].gbuffer;
  for (int y = 0; y < lh; ++y)
    for (int x = 0; x < lw; ++x) {
      float fmax = 0.0f;
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          const int px = 2 * x + i, py = 2 * y + j;
          if (!e.at(px, py)) continue;
          m1.at(x, y) = 1;
          if (g.hit.at(px, py) && g.depth.at(px, py) > 0.0f)
            fmax = std::max(fmax, c.ssao.radius * f.view.focal / g.depth.at(px, py));
        }
      if (m1.at(x, y)) k1.at(x, y) = static_cast<int16_t>(std::min(c.effectMask.cap, static_cast<int>(std::floor(fmax / 2.0f + 0.5f))));
    }
  int effectPixels = 0;
  const CoverageArms arms = coverageArms(f), mrrArms = coverageArms(mrr.frame);
  for (int y = 0; y < lh; ++y)
    for (int x = 0; x < lw; ++x) {
      int nearest = 1 << 20;
      bool reached = false;
      for (int v = 0; v < lh; ++v)
        for (int u = 0; u < lw; ++u)
          if (m1.at(u, v)) {
            const int d = std::max(std::abs(u - x), std::abs(v - y));
            nearest = std::min(nearest, d);
            reached = reached || d <= k1.at(u, v);
          }
      if (nearest <= r || !reached) continue;
      EXPECT_EQ(coverageName(coverageReason(arms, f, 1, x, y)), std::string("effect")) << x << "," << y;
      // mrr does not shade it at level 1, unless level 0 shades inside it
      const Coverage inMrr = coverageReason(mrrArms, mrr.frame, 1, x, y);
      EXPECT_TRUE(inMrr == Coverage::None || inMrr == Coverage::Closure) << coverageName(inMrr);
      if (effectPixels++ == 0) {  // and the probe says so, in its story too
        const nlohmann::json p = probePixel(f, 2 * x, 2 * y);
        EXPECT_EQ(reasonAt(p, 1), "effect");
        EXPECT_NE(formatProbe(p).find("why: effect"), std::string::npos) << formatProbe(p);
      }
    }
  EXPECT_GT(effectPixels, 0) << "no level-1 pixel lies out of the blur and within reach";

  // 3. the reasons are the frame's stencil: covered exactly where S = 1, on every level
  for (int l = 0; l < kLevelCount; ++l) {
    const ImageU8& st = f.levels[static_cast<size_t>(l)].masks.stencil;
    for (int y = 0; y < st.height; ++y)
      for (int x = 0; x < st.width; ++x) {
        const Coverage why = coverageReason(arms, f, l, x, y);
        ASSERT_EQ(st.at(x, y) != 0, why != Coverage::None && why != Coverage::Limit && why != Coverage::Trim)
            << "level " << l << " " << x << "," << y << " " << coverageName(why);
      }
  }
}

// The ablation's effect-only arm (bench variant +e): level 0 holds nothing, each widened level
// exactly the pixels the widening adds, and no level is covered for an edge.
TEST(CoverageWhy, EffectOnlyShadesWhatTheWideningAdds) {
  Settings s = ssaoSettings(160, 96, 8, Mode::MrrEffect);
  s.effectMask.budget = 0.0f;  // the a-priori arms alone
  const auto both = renderScene("builtin:demo", s);
  s.effectMask.effectOnly = true;
  const auto only = renderScene("builtin:demo", s);
  const CoverageArms arms = coverageArms(both.frame);
  EXPECT_EQ(test::countSet(only.frame.levels[0].masks.mask), 0);
  for (int l = 1; l < only.frame.constants.coarsestEnabled; ++l) {
    const ImageU8& m = only.frame.levels[static_cast<size_t>(l)].masks.mask;
    const ImageU8& geometry = arms.stages.geometry[static_cast<size_t>(l)];
    const ImageU8& widened = both.frame.levels[static_cast<size_t>(l)].masks.mask;
    ASSERT_EQ(m.data.size(), widened.data.size());
    for (size_t i = 0; i < m.data.size(); ++i) ASSERT_EQ(m.data[i], widened.data[i] && !geometry.data[i]) << l << " " << i;
    EXPECT_GT(test::countSet(m), 0) << "level " << l;
  }
  const CoverageArms onlyArms = coverageArms(only.frame);
  for (int l = 0; l < kLevelCount; ++l) {
    const ImageU8& st = only.frame.levels[static_cast<size_t>(l)].masks.stencil;
    for (int y = 0; y < st.height; ++y)
      for (int x = 0; x < st.width; ++x)
        ASSERT_NE(coverageReason(onlyArms, only.frame, l, x, y), Coverage::Geometry) << l << " " << x << "," << y;
  }
  EXPECT_LT(only.frame.shadedPixelsTotal, both.frame.shadedPixelsTotal);
}

// With a gaze and a high ppd, an edge pixel far from the gaze is not covered at level 0, and the
// probe says the limit cleared it; with the a-posteriori term, some pixel is covered for its marks,
// its parent's range over τ.
TEST(CoverageWhy, TheLevelLimitAndTheMarks) {
  Settings s = ssaoSettings(160, 96, 8, Mode::MrrEffect);
  s.foveation.gaze = true;
  s.foveation.gazeX = 0;
  s.foveation.gazeY = 0;
  s.foveation.ppd = 150.0f;
  const auto fov = renderScene("builtin:demo", s);
  const FrameResult& f = fov.frame;
  int limited = 0;
  for (int y = 0; y < f.constants.height && limited < 5; ++y)
    for (int x = 0; x < f.constants.width && limited < 5; ++x)
      if (f.edges.combined.at(x, y) && f.levelLimit.at(x, y, kLimitLevel) > 0) {
        const nlohmann::json p = probePixel(f, x, y);
        EXPECT_EQ(reasonAt(p, 0), "limit") << x << "," << y;
        EXPECT_EQ(f.levels[0].masks.stencil.at(x, y), 0);
        ++limited;
      }
  EXPECT_GT(limited, 0);

  s = ssaoSettings(160, 96, 8, Mode::MrrEffect);
  s.effectMask.posterior = 0.05f;
  s.effectMask.budget = 0.0f;  // τ_v's marks (SPEC §12.2), every one over τ
  const auto post = renderScene("builtin:demo", s);
  const CoverageArms arms = coverageArms(post.frame);
  int marked = 0;
  for (int l = 0; l < post.frame.constants.coarsestEnabled && marked == 0; ++l) {
    const ImageU8& st = post.frame.levels[static_cast<size_t>(l)].masks.stencil;
    for (int y = 0; y < st.height && marked == 0; ++y)
      for (int x = 0; x < st.width && marked == 0; ++x)
        if (coverageReason(arms, post.frame, l, x, y) == Coverage::Marks && arms.marks[static_cast<size_t>(l)].at(x, y)) {
          const int s2 = post.frame.constants.levels[static_cast<size_t>(l)].scale;
          const nlohmann::json w = probePixel(post.frame, x * s2, y * s2)["levels"][static_cast<size_t>(l)]["why"];
          EXPECT_EQ(w["reason"], "marks");
          EXPECT_GT(w["mark_range"].get<double>(), 0.05);
          ++marked;
        }
  }
  EXPECT_GT(marked, 0) << "no pixel covered for its marks alone";
}

}  // namespace
}  // namespace mrr
