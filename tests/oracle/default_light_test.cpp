// A default light that lights the view: a scene without a light of its own gets the
// candidate direction that lights the most of the default view's visible surface; scenes with
// a light (every built-in) keep theirs bit for bit. Checked against the oracle's own SSM shadow
// test on the rendered frame, not only the host's small estimate.
#include <gtest/gtest.h>

#include <iostream>

#include "common/error.h"
#include "cpu_ref/pipeline.h"
#include "scenes/builtin.h"
#include "scenes/catalog.h"
#include "scenes/default_light.h"
#include "tests/oracle/render_helpers.h"
#include "tests/test_support.h"

namespace mrr {
namespace {

// The share of the frame's surface pixels that the oracle's one-tap shadow test lights.
double renderedLitShare(const Scene& scene, const Camera& camera) {
  Settings s = defaultSettings(Effect::Ssm);
  s.width = 320;
  s.height = 180;
  s.ssm.samples = 4;
  s.ssm.shadowMapSize = 1024;
  s.mode = Mode::Full;
  s.neverSlower = false;
  const Renderer renderer(scene);
  const FrameResult f = renderer.render(camera, makeConstants(s, framedSize(scene, camera, 320.0f / 180.0f).size));
  const GBuffer& g = f.levels[0].gbuffer;
  int64_t surface = 0, lit = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      if (g.hit.at(x, y)) {
        ++surface;
        lit += f.shadowLit.at(x, y) != 0;
      }
  return surface ? static_cast<double>(lit) / static_cast<double>(surface) : 0.0;
}

// A room 6 × 2.5 × 4 open on its −z side (a loggia, a hotel room's missing wall: the light must
// come in from there), with a ceiling, a floor and a bed.
Scene openRoom() {
  Scene s = makeBuiltinScene("plane");
  s.meshes.clear();
  s.hasLight = false;
  s.light = DirectionalLight{};
  s.cameras.clear();
  auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d) {
    Mesh m;
    m.name = "q";
    m.positions = {a, b, c, d};
    m.indices = {0, 1, 2, 0, 2, 3};
    computeVertexNormals(m);
    s.meshes.push_back(std::move(m));
  };
  quad({-3, 0, -2}, {-3, 0, 2}, {3, 0, 2}, {3, 0, -2});              // floor, facing up
  quad({-3, 2.5f, -2}, {3, 2.5f, -2}, {3, 2.5f, 2}, {-3, 2.5f, 2});  // ceiling, facing down
  quad({-3, 0, 2}, {-3, 2.5f, 2}, {3, 2.5f, 2}, {3, 0, 2});          // back (+z) wall, facing −z
  quad({-3, 0, -2}, {-3, 2.5f, -2}, {-3, 2.5f, 2}, {-3, 0, 2});      // −x wall, facing +x
  quad({3, 0, -2}, {3, 0, 2}, {3, 2.5f, 2}, {3, 2.5f, -2});          // +x wall, facing −x
  // a roof slab above the ceiling, overhanging the open side
  quad({-3.5f, 2.8f, -3}, {-3.5f, 2.8f, 2.5f}, {3.5f, 2.8f, 2.5f}, {3.5f, 2.8f, -3});
  return s;
}

TEST(DefaultLight, CandidatesStartWithTheBuiltInDefault) {
  const std::vector<glm::vec3>& c = defaultLightCandidates();
  ASSERT_EQ(c.size(), 17u);
  EXPECT_EQ(c[0], glm::normalize(DirectionalLight{}.direction));
  for (const glm::vec3& d : c) {
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
    EXPECT_LT(d.y, 0.0f) << "every candidate shines from the upper hemisphere";
  }
}

TEST(DefaultLight, ScenesWithALightKeepIt) {
  for (const std::string& name : builtinSceneNames()) {
    SceneRequest request;
    request.scene = "builtin:" + name;
    const Scene scene = loadRequestedScene(request);
    EXPECT_EQ(scene.light.direction, makeBuiltinScene(name).light.direction) << name;
    EXPECT_EQ(scene.lightOrigin.source, "the scene") << name;
    EXPECT_EQ(scene.lightOrigin.candidate, -1) << name;
  }
  // --light-dir wins over any choice
  SceneRequest request;
  request.scene = "builtin:plane";
  request.lightToward = glm::vec3(0, 1, 0);
  EXPECT_EQ(loadRequestedScene(request).lightOrigin.source, "--light-dir");
}

TEST(DefaultLight, AnOpenRoomGetsALightThroughItsOpening) {
  const Scene scene = openRoom();
  const Camera camera = lookAt({0.0f, 1.3f, -1.8f}, {0.0f, 0.8f, 2.0f}, 60.0f);  // inside, looking at the back
  const DefaultLightChoice a = chooseDefaultLight(scene, camera, 16.0f / 9.0f);
  const DefaultLightChoice b = chooseDefaultLight(scene, camera, 16.0f / 9.0f);
  EXPECT_EQ(a.chosen, b.chosen);
  EXPECT_EQ(a.shares, b.shares);  // deterministic
  ASSERT_EQ(a.shares.size(), defaultLightCandidates().size());
  EXPECT_GT(a.surface, 5000);
  EXPECT_LT(a.shares[0], 0.2f) << "the built-in default comes from +z, over the roof";
  // the best candidate, the earliest of equals
  for (size_t i = 0; i < a.shares.size(); ++i) {
    EXPECT_LE(a.shares[i], a.shares[static_cast<size_t>(a.chosen)]) << i;
    if (static_cast<int>(i) < a.chosen) EXPECT_LT(a.shares[i], a.shares[static_cast<size_t>(a.chosen)]) << i;
  }
  // (the roof overhangs the opening and the room is deep: 30° is as low as a candidate goes)
  EXPECT_GE(a.shares[static_cast<size_t>(a.chosen)], 0.25f);
  EXPECT_GT(a.direction.z, 0.0f) << "the light travels in through the open −z side";
  // the oracle's own shadow test on the rendered frame agrees
  Scene lit = scene, unlit = scene;
  lit.light.direction = a.direction;
  const double chosen = renderedLitShare(lit, camera), builtin = renderedLitShare(unlit, camera);
  RecordProperty("rendered_lit_share_builtin", std::to_string(builtin));
  RecordProperty("rendered_lit_share_chosen", std::to_string(chosen));
  EXPECT_GE(chosen, 0.25) << "builtin " << builtin;
  EXPECT_GT(chosen, builtin + 0.2);
  EXPECT_NEAR(chosen, a.shares[static_cast<size_t>(a.chosen)], 0.1) << "the host's estimate and the oracle agree";
}

TEST(DefaultLight, SharedScenesWithoutALightGetTheBestCandidate) {
  for (const std::string name : {"cornell", "arcade", "apartment"}) {
    SceneRequest request;
    request.scene = name;
    ResolvedScene rs;
    try {
      rs = resolveScene(request);
    } catch (const MrrError& e) {
      std::cerr << "skipped " << name << ": " << e.what() << "\n";
      continue;
    }
    const LightOrigin& o = rs.scene.lightOrigin;
    ASSERT_GE(o.candidate, 0) << name;
    EXPECT_GE(o.litShare, o.builtinLitShare) << name;
    Scene builtin = rs.scene;
    builtin.light = DirectionalLight{};
    const double before = renderedLitShare(builtin, rs.camera), after = renderedLitShare(rs.scene, rs.camera);
    std::cerr << name << ": candidate " << o.candidate << " (" << o.source << "), host estimate "
              << o.builtinLitShare << " -> " << o.litShare << ", the oracle's SSM shadow test " << before << " -> "
              << after << "\n";
    EXPECT_GE(after, before - 0.05) << name;
  }
}

}  // namespace
}  // namespace mrr

#include "compare/parity/constant_effect.h"

namespace mrr {
namespace {

TEST(ConstantEffect, AFlatPlanesAoIsConstantAndTheDemosIsNot) {
  // builtin:plane, a square filling the view: AO 1 everywhere (SPEC §2, §6), a frame that checks little
  const test::Rendered plane = test::renderScene("builtin:plane", test::ssaoSettings(96, 54, 8));
  EXPECT_TRUE(effectIsConstant(plane.frame));
  const EffectRange r = effectRange(plane.frame);
  EXPECT_GT(r.surfacePixels, 0);
  EXPECT_LT(r.hi - r.lo, kConstantEffectRange);
  const test::Rendered demo = test::renderScene("builtin:demo", test::ssaoSettings(96, 54, 8));
  EXPECT_FALSE(effectIsConstant(demo.frame));
}

}  // namespace
}  // namespace mrr

namespace mrr {
namespace {

// The automatic radii's basis (docs/spec.md §6): a wall square-on at distance d, filling the view,
// frames 2 d tan(fov/2); a second wall behind the first changes nothing (it is hidden); a view
// that sees no surface falls back to the scene's diagonal; and the radii are those fractions of it.
TEST(FramedSize, IsTheViewsHeightAtTheMedianDepthOfWhatItSees) {
  Scene s = makeBuiltinScene("plane");
  s.meshes.clear();
  s.cameras.clear();
  auto wall = [&](float z, float half) {
    Mesh m;
    m.name = "wall";
    m.positions = {{-half, -half, z}, {half, -half, z}, {half, half, z}, {-half, half, z}};
    m.indices = {0, 1, 2, 0, 2, 3};
    computeVertexNormals(m);
    s.meshes.push_back(std::move(m));
  };
  wall(0.0f, 50.0f);
  const Camera camera = lookAt({0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 60.0f);
  const FramedSize f = framedSize(s, camera, 16.0f / 9.0f);
  EXPECT_EQ(f.surface, 128 * 72);
  EXPECT_NEAR(f.medianDepth, 4.0f, 1e-4f);
  EXPECT_NEAR(f.size, 8.0f * std::tan(glm::radians(30.0f)), 1e-4f);
  wall(-3.0f, 60.0f);  // hidden behind the first: the same median
  EXPECT_NEAR(framedSize(s, camera, 16.0f / 9.0f).medianDepth, 4.0f, 1e-4f);
  // Half the view on a nearer wall (x < 0 at depth 2): the median is the lower middle, on the
  // far wall's side only when more than half of the pixels are there.
  Mesh near;
  near.name = "near";
  near.positions = {{-50.0f, -50.0f, 2.0f}, {-0.001f, -50.0f, 2.0f}, {-0.001f, 50.0f, 2.0f}, {-50.0f, 50.0f, 2.0f}};
  near.indices = {0, 1, 2, 0, 2, 3};
  computeVertexNormals(near);
  s.meshes.push_back(near);
  EXPECT_NEAR(framedSize(s, camera, 16.0f / 9.0f).medianDepth, 2.0f, 1e-4f);
  // Looking away: nothing in view, the diagonal.
  const FramedSize away = framedSize(s, lookAt({0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 8.0f}, 60.0f), 16.0f / 9.0f);
  EXPECT_EQ(away.surface, 0);
  EXPECT_EQ(away.size, s.bounds().diagonal());
  // The constants: 15% (SSAO) and 30% (SSGI) of it; an explicit radius wins.
  Settings settings = defaultSettings(Effect::Ssao);
  const Constants k = makeConstants(settings, f.size);
  EXPECT_EQ(k.ssao.radius, SsaoSettings::kAutoRadiusFraction * f.size);
  EXPECT_EQ(k.ssgi.radius, SsgiSettings::kAutoRadiusFraction * f.size);
  EXPECT_FLOAT_EQ(k.ssao.radius, 0.15f * f.size);
  settings.ssao.radius = 0.7f;
  EXPECT_EQ(makeConstants(settings, f.size).ssao.radius, 0.7f);
}

// resolveScene carries it, at the request's aspect, for its camera.
TEST(FramedSize, ResolveSceneGivesTheRequestsView) {
  SceneRequest req;
  req.scene = "builtin:corner";
  const ResolvedScene rs = resolveScene(req);
  const FramedSize f = framedSize(rs.scene, rs.camera, req.aspect);
  EXPECT_EQ(rs.framed.size, f.size);
  EXPECT_GT(rs.framed.surface, 0);
  EXPECT_LT(rs.framed.size, rs.scene.bounds().diagonal());
}

}  // namespace
}  // namespace mrr
