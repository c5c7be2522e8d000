// SSM (PCSS) and SSGI: analytic cases, shadow edges, and the invariants every effect keeps.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "cpu_ref/masks.h"
#include "cpu_ref/probe.h"
#include "cpu_ref/ssm.h"
#include "tests/oracle/render_helpers.h"
#include "tests/test_support.h"

namespace mrr {
namespace {

using test::countSet;

Settings effectSettings(Effect e, int w, int h, int samples, Mode mode = Mode::Mrr) {
  Settings s = defaultSettings(e);
  s.width = w;
  s.height = h;
  s.mode = mode;
  s.setSamples(samples);
  s.neverSlower = false;  // these test the method's stages, which a fallback would skip (SPEC §11)
  return s;
}

glm::vec3 worldAt(const FrameResult& f, int x, int y) {
  return f.view.toWorld(f.levels[0].gbuffer.positionAt(x, y));
}

TEST(Ssm, UmbraIsDarkAndOpenGroundIsExactlyLit) {
  const auto r = test::renderScene("builtin:shadows", effectSettings(Effect::Ssm, 200, 150, 100, Mode::Full));
  const FrameResult& f = r.frame;
  int umbra = 0, open = 0;
  for (int y = 0; y < 150; ++y)
    for (int x = 0; x < 200; ++x) {
      if (!f.levels[0].gbuffer.hit.at(x, y)) continue;
      const glm::vec3 p = worldAt(f, x, y);
      if (p.y > 0.01f) continue;  // ground only
      // Under the high slab's shadow centre: the slab (half-size 1, height 2.5) shadows the
      // ground around (3, 0, 0) + 2.5·(0.15, 0.1)/1 — well inside, it is umbra.
      if (glm::length(glm::vec2(p.x - 3.375f, p.z - 0.25f)) < 0.4f) {
        EXPECT_EQ(f.final().at(x, y), 0.0f) << x << "," << y;
        ++umbra;
      }
      // Far from both slabs no blocker is in any search region: V is 1 exactly.
      if (std::fabs(p.x) > 6.0f || std::fabs(p.z) > 5.0f) {
        ASSERT_EQ(f.final().at(x, y), 1.0f) << x << "," << y;
        ++open;
      }
    }
  EXPECT_GT(umbra, 20);
  EXPECT_GT(open, 1000);
}

TEST(Ssm, PenumbraWidensWithTheReceiversDistanceFromTheBlocker) {
  // PCSS: penumbra = (d_receiver − d_blocker)·2tan(θ/2). The slab 2.5 above the ground must
  // cast a wider penumbra than the one 0.5 above it: count partly lit ground pixels.
  const auto r = test::renderScene("builtin:shadows", effectSettings(Effect::Ssm, 320, 240, 196, Mode::Full));
  const FrameResult& f = r.frame;
  int lowPartial = 0, highPartial = 0;
  float lowWidth = 0.0f, highWidth = 0.0f;
  for (int y = 0; y < 240; ++y)
    for (int x = 0; x < 320; ++x) {
      if (!f.levels[0].gbuffer.hit.at(x, y)) continue;
      const glm::vec3 p = worldAt(f, x, y);
      const float v = f.final().at(x, y);
      if (p.y > 0.01f || v <= 0.0f || v >= 1.0f) continue;
      SsmDetail d;
      ssmAt(f.levels[0].gbuffer, f.shadowMap, f.view, f.constants.ssm, x, y, &d);
      if (p.x < 0.0f) {
        ++lowPartial;
        lowWidth = std::max(lowWidth, d.penumbraWorld);
      } else {
        ++highPartial;
        highWidth = std::max(highWidth, d.penumbraWorld);
      }
    }
  EXPECT_GT(highWidth, 3.0f * lowWidth);  // 2.5 vs 0.5 above the ground: about 5×
  EXPECT_GT(highPartial, 2 * lowPartial);
}

TEST(Ssm, PcfSampleSaysWhatSsmAtPays) {
  // SPEC §11's H_a and H_p: the rule's sample asks one pixel in 8×8 what PCSS pays there. It must
  // be ssmAt's own answer at (8x + 4, 8y + 4): PCF where pcfTaps > 0, the search alone where it
  // faces the light and finds nothing, nothing where it faces away (sky: the search, assumed).
  // Lit from above and from below, every kind occurs, and the search sees blockers the one-tap
  // test does not.
  int pays = 0, searchOnly = 0, facesAway = 0, paysWhereOneTapIsLit = 0;
  auto check = [&](const FrameResult& f) {
    const GBuffer& g = f.levels[0].gbuffer;
    const ImageU8 sample = pcfSample(g, f.shadowMap, f.view, f.constants.ssm);
    ASSERT_EQ(sample.width, 26);  // ⌈203 / 8⌉
    ASSERT_EQ(sample.height, 19);
    for (int y = 0; y < sample.height; ++y)
      for (int x = 0; x < sample.width; ++x) {
        const int px = std::min(x * 8 + 4, 202), py = std::min(y * 8 + 4, 148);
        SsmDetail d;
        ssmAt(g, f.shadowMap, f.view, f.constants.ssm, px, py, &d);
        const uint8_t expected = !g.hit.at(px, py) ? kPcfSampleSearch
                                 : !d.facesLight   ? kPcfSampleNone
                                 : d.pcfTaps > 0   ? kPcfSamplePcf
                                                   : kPcfSampleSearch;
        ASSERT_EQ(pcfSampleClass(sample.at(x, y)), expected) << x << "," << y;
        if (expected == kPcfSampleNone || !g.hit.at(px, py)) EXPECT_EQ(pcfSampleFootprintSteps(sample.at(x, y)), 0);
        pays += expected == kPcfSamplePcf;
        searchOnly += g.hit.at(px, py) && expected == kPcfSampleSearch;
        facesAway += expected == kPcfSampleNone;
        paysWhereOneTapIsLit += d.pcfTaps > 0 && f.shadowLit.at(px, py);
      }
  };
  auto r = test::renderScene("builtin:shadows", effectSettings(Effect::Ssm, 203, 149, 49, Mode::Full));
  check(r.frame);
  EXPECT_GT(pays, 10);
  EXPECT_GT(searchOnly, 10);
  EXPECT_GT(paysWhereOneTapIsLit, 0) << "the search sees blockers the one-tap test does not";
  r.scene->light.direction = glm::normalize(glm::vec3(0.3f, 1.0f, -0.4f));  // from below: the ground faces away
  check(r.renderer->render(r.camera, r.frame.constants));
  EXPECT_GT(facesAway, 100);
}

TEST(Ssm, TheSampledFootprintIsTheMapDistanceBetweenNeighbours) {
  // SPEC §11's map footprint, analytically: on the fronto-parallel plane the camera at z = 5 steps
  // h = 2 · 5 tan(30°) / H world units a pixel, along x across and y down; the map sees a step d
  // at |d − (d·l) l| (l: the light's forward), so f = (h / texel) · (√(1 − l_x²) + √(1 − l_y²)) / 2
  // at every pixel, in steps of a quarter texel. Halving the frame's side doubles it.
  for (const int width : {160, 320}) {
    const int height = width * 9 / 16;
    const auto r = test::renderScene("builtin:plane", effectSettings(Effect::Ssm, width, height, 49, Mode::Full));
    const FrameResult& f = r.frame;
    const ShadowMap& map = f.shadowMap;
    const float step = 2.0f * 5.0f * std::tan(glm::radians(30.0f)) / static_cast<float>(height);
    const glm::vec3 l = map.forward;
    const float expected =
        step / map.texel * 0.5f * (std::sqrt(1.0f - l.x * l.x) + std::sqrt(1.0f - l.y * l.y));
    ASSERT_GT(expected, 1.0f);
    ASSERT_LT(expected, kMaxFootprintTexels);
    const ImageU8 sample = pcfSample(f.levels[0].gbuffer, map, f.view, f.constants.ssm);
    int checked = 0;
    for (int y = 0; y < sample.height; ++y)
      for (int x = 0; x < sample.width; ++x) {
        const uint8_t v = sample.at(x, y);
        if (!f.levels[0].gbuffer.hit.at(std::min(x * 8 + 4, width - 1), std::min(y * 8 + 4, height - 1))) {
          EXPECT_EQ(v, kPcfSampleSearch) << "sky: the search assumed, no footprint";
          continue;
        }
        ASSERT_EQ(pcfSampleClass(v), kPcfSampleSearch) << "nothing blocks the plane";
        EXPECT_NEAR(pcfSampleFootprintSteps(v) / kFootprintSteps, expected, 0.5f / kFootprintSteps + 1e-3f) << x << "," << y;
        ++checked;
      }
    EXPECT_GT(checked, static_cast<int>(sample.data.size()) / 2) << "the plane fills most of the view";
    // `mrr probe` says the same of any pixel, unrounded
    const nlohmann::json p = probePixel(f, width / 2, height / 2);
    EXPECT_NEAR(p["levels"][0]["ssm"]["map_footprint_texels"].get<double>(), expected, 1e-3 * expected);
    // and the rule's count: every searching pixel at its block's sample's footprint
    FrameCounts n;
    countHits(n, f.levels[0].gbuffer.hit, sample, f.constants, nullptr);
    ASSERT_GT(n.searchedPixels, 0);
    EXPECT_NEAR(footprintTexels(f.constants.levels[0], n), expected, 0.5 / kFootprintSteps + 1e-3);
    EXPECT_NEAR(footprintTexels(f.constants.levels[1], n), std::min(2.0 * expected, double{kMaxFootprintTexels}),
                1.0 / kFootprintSteps + 2e-3) << "a level-1 pixel's neighbours lie twice as far, at most a line";
  }
}

TEST(Ssm, ShadowEdgesPutTheFullResStencilAlongShadowBoundaries) {
  const auto r = test::renderScene("builtin:shadows", effectSettings(Effect::Ssm, 200, 150, 100));
  const FrameResult& f = r.frame;
  ASSERT_FALSE(f.edges.shadow.empty());
  int shadowOnly = 0;
  for (int y = 0; y < 150; ++y)
    for (int x = 0; x < 200; ++x) {
      if (!f.edges.shadow.at(x, y)) continue;
      EXPECT_TRUE(f.levels[0].masks.stencil.at(x, y));
      shadowOnly += !f.edges.normal.at(x, y) && !f.edges.depth.at(x, y) && !f.edges.background.at(x, y);
    }
  EXPECT_GT(shadowOnly, 30);  // on the open ground, where no geometric edge is
}

TEST(Ssm, ShadowEdgesOnARealScene) {
  const std::string file = "dream-apartment/dream-apartment.glb";
  if (!test::haveSharedScene(file)) GTEST_SKIP() << "shared scene missing: " << test::sharedScene(file);
  const auto r = test::renderScene("apartment", effectSettings(Effect::Ssm, 320, 180, 16));
  const FrameResult& f = r.frame;
  int shadowOnly = 0;
  for (size_t i = 0; i < f.edges.shadow.data.size(); ++i)
    shadowOnly += f.edges.shadow.data[i] && !f.edges.normal.data[i] && !f.edges.depth.data[i];
  EXPECT_GT(countSet(f.edges.shadow), 100);
  EXPECT_GT(shadowOnly, 50);
}

TEST(Ssgi, NoLightNoIndirectLight) {
  SceneRequest req;
  req.scene = "builtin:redwall";
  ResolvedScene rs = resolveScene(req);
  rs.scene.light.color = glm::vec3(0.0f);
  const Renderer renderer(rs.scene);
  const FrameResult f =
      renderer.render(rs.camera, makeConstants(effectSettings(Effect::Ssgi, 96, 64, 24), rs.framed.size));
  for (float v : f.final().data) ASSERT_EQ(v, 0.0f);
}

TEST(Ssgi, RedWallBleedsRedNeverGreenOnTheFloor) {
  const auto r = test::renderScene("builtin:redwall", effectSettings(Effect::Ssgi, 160, 120, 80, Mode::Full));
  const FrameResult& f = r.frame;
  // Bands of floor at increasing distance from the wall (z = −2): the red falls off.
  double nearSum = 0, farSum = 0;
  int near = 0, far = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      if (!f.levels[0].gbuffer.hit.at(x, y)) continue;
      const glm::vec3 p = worldAt(f, x, y);
      if (p.y > 0.01f) continue;  // floor
      const float red = f.final().at(x, y, 0), green = f.final().at(x, y, 1);
      ASSERT_EQ(green, 0.0f) << "green light on the floor at " << x << "," << y;  // only the red wall sends
      if (std::fabs(p.x) > 4.0f) continue;
      if (p.z < -1.75f) {  // within 0.25 of the wall
        EXPECT_GT(red, 0.0f) << x << "," << y;
        nearSum += red;
        ++near;
      } else if (p.z > -1.25f && p.z < -0.75f) {
        farSum += red;
        ++far;
      }
    }
  ASSERT_GT(near, 10);
  ASSERT_GT(far, 10);
  EXPECT_GT(nearSum / near, 0.01);
  EXPECT_GT(nearSum / near, 3.0 * farSum / far);
}

TEST(Ssgi, ALonePlaneReceivesNothing) {
  const auto r = test::renderScene("builtin:plane", effectSettings(Effect::Ssgi, 64, 48, 80, Mode::Full));
  for (float v : r.frame.final().data) ASSERT_EQ(v, 0.0f);
}

TEST(Ssgi, DropsTheHalfLevelAndPoolsStraightIntoQuarter) {
  const auto r = test::renderScene("builtin:demo", effectSettings(Effect::Ssgi, 128, 96, 24));
  const FrameResult& f = r.frame;
  EXPECT_FALSE(f.constants.levels[1].enabled);
  EXPECT_EQ(f.levels[1].shadedPixels, 0);
  const ImageU8 pooled = maxPool(f.levels[0].masks.stencil, 4);
  for (size_t i = 0; i < pooled.data.size(); ++i) ASSERT_LE(pooled.data[i], f.levels[2].masks.stencil.data[i]);
  EXPECT_EQ(f.final().channels, 3);
}

class EveryEffect : public ::testing::TestWithParam<Effect> {};

TEST_P(EveryEffect, CoversEveryPixelAtOddSizes) {
  for (auto [w, h] : {std::pair{1, 1}, std::pair{7, 5}, std::pair{97, 61}}) {
    const auto r = test::renderScene("builtin:demo", effectSettings(GetParam(), w, h, GetParam() == Effect::Ssm ? 16 : 8));
    const FrameResult& f = r.frame;
    for (float v : f.blend.alpha[static_cast<size_t>(f.constants.coarsestEnabled)].data) ASSERT_EQ(v, 1.0f);
    for (float v : f.final().data) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
  }
}

TEST_P(EveryEffect, OneTwoAndEightThreadsGiveIdenticalBits) {
  const Settings s = effectSettings(GetParam(), 123, 71, GetParam() == Effect::Ssm ? 25 : 16);
  std::vector<test::Rendered> runs;
  for (size_t threads : {1u, 2u, 8u}) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    runs.push_back(test::renderScene("builtin:demo", s));
  }
  for (size_t k = 1; k < runs.size(); ++k) {
    const ImageF &a = runs[0].frame.final(), &b = runs[k].frame.final();
    ASSERT_EQ(a.data.size(), b.data.size());
    EXPECT_EQ(std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)), 0);
    EXPECT_EQ(runs[0].frame.edges.combined.data, runs[k].frame.edges.combined.data);
    EXPECT_EQ(runs[0].frame.shadowMap.depth.data, runs[k].frame.shadowMap.depth.data);
  }
}

INSTANTIATE_TEST_SUITE_P(Effects, EveryEffect, ::testing::Values(Effect::Ssao, Effect::Ssm, Effect::Ssgi),
                         [](const auto& info) { return toString(info.param); });

}  // namespace
}  // namespace mrr
