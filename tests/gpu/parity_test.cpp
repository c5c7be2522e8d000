// The port against the oracle, stage by stage (SPEC §8): G-buffer, edges, masks and stencils,
// and SSAO drawn with the stencil test; plus the GLSL hash against the host bit for bit; the
// peers (uniform-k, tiles) and the never-slower rule through compareFrames, with planted faults.
// Each stage is also compared with the oracle's stage computed from the port's own inputs
// (cascade awareness), so a shader bug is not hidden by, nor blamed on, upstream noise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>

#include "common/cost_model.h"
#include "common/error.h"
#include "common/hash.h"
#include "common/stages.h"
#include "common/tolerance.h"
#include "compare/parity/parity.h"
#include "cpu_ref/gbuffer.h"
#include "cpu_ref/peers.h"
#include "cpu_ref/probe.h"
#include "cpu_ref/ssao.h"
#include "cpu_ref/ssgi.h"
#include "cpu_ref/ssm.h"
#include "gpu/context.h"
#include "gpu/edges.h"
#include "gpu/faults.h"
#include "gpu/gbuffer.h"
#include "gpu/masks.h"
#include "gpu/pipeline.h"
#include "gpu/program.h"
#include "gpu/shadowmap.h"
#include "gpu/ssao.h"
#include "gpu/ssgi.h"
#include "gpu/ssm.h"
#include "tests/gpu/gl_test.h"
#include "tests/oracle/render_helpers.h"
#include "tests/test_support.h"
#include "cpu_ref/edges.h"

namespace mrr {
namespace {

// Every threshold comes from the one table, common/tolerance.h.
const ToleranceRule& kHit = tolerance("gbuffer.hit");
const ToleranceRule& kDepth = tolerance("gbuffer.depth");
const ToleranceRule& kNormal = tolerance("gbuffer.normal");
const ToleranceRule& kEdges = tolerance("edges");
const ToleranceRule& kEdgesSame = tolerance("edges.same_input");
const ToleranceRule& kMasksSame = tolerance("masks.same_input");
const ToleranceRule& kAlphaSame = tolerance("alpha.same_input");
const ToleranceRule& kStencil = tolerance("stencil");
const ToleranceRule& kSsaoSame = tolerance("ssao.same_input");
const ToleranceRule& kFinal = tolerance("final");

class GpuParity : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    MRR_REQUIRE_GL_OR_SKIP();
    context_ = std::make_unique<gpu::GlContext>();
  }
  std::unique_ptr<gpu::GlContext> context_;
};

TEST_P(GpuParity, StagesMatchTheOracle) {
  const Settings s = test::ssaoSettings(161, 97, 4);  // odd size: exercises the padding
  std::string spec = GetParam();
  if (spec == "arcade" && !test::haveSharedScene("sascha-arcade/subpass_scene_opaque.gltf"))
    GTEST_SKIP() << "shared scene missing: " << test::sharedScene("sascha-arcade/subpass_scene_opaque.gltf");
  if (spec != "arcade") spec = "builtin:" + spec;
  const auto r = test::renderScene(spec, s);
  const FrameResult& f = r.frame;
  const gpu::GpuScene scene(*r.scene);
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = f.constants.levels[static_cast<size_t>(l)];
    const GBuffer& cpu = f.levels[static_cast<size_t>(l)].gbuffer;
    const GBuffer g = gpu::renderGBuffer(scene, f.view, lc);
    ASSERT_EQ(g.width, cpu.width);
    int64_t hitMismatch = 0, both = 0, depthOff = 0, normalOff = 0;
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) {
        if (g.hit.at(x, y) != cpu.hit.at(x, y)) {
          ++hitMismatch;
          continue;
        }
        if (!g.hit.at(x, y)) continue;
        ++both;
        const float zc = cpu.depth.at(x, y);
        depthOff += std::fabs(g.depth.at(x, y) - zc) > kDepth.pixelThreshold * zc;
        normalOff += 1.0 - glm::dot(g.normalAt(x, y), cpu.normalAt(x, y)) > kNormal.pixelThreshold;
      }
    const double pixels = static_cast<double>(g.width) * g.height;
    EXPECT_LE(hitMismatch / pixels, kHit.shareOver) << "level " << l;
    EXPECT_LE(depthOff / std::max(1.0, static_cast<double>(both)), kDepth.shareOver) << "level " << l;
    EXPECT_LE(normalOff / std::max(1.0, static_cast<double>(both)), kNormal.shareOver) << "level " << l;
  }
  // Edges: against the oracle's, and against the oracle's from the port's own G-buffer.
  gpu::Framebuffer g0(f.constants.levels[0].width, f.constants.levels[0].height, 3, true);
  gpu::drawGBuffer(scene, f.view, g0);
  const GBuffer g0Read = gpu::readGBuffer(g0);
  // The coarse G-buffers (SPEC §1): the port's subsample of its own level 0, bit for bit the
  // oracle's subsampleGBuffer of the same level 0.
  for (int l = 1; l < kLevelCount; ++l) {
    const LevelConstants& lc = f.constants.levels[static_cast<size_t>(l)];
    gpu::Framebuffer gl(lc.width, lc.height, 3, true);
    gpu::subsampleGBuffer(scene, g0, lc, gl);
    const GBuffer port = gpu::readGBuffer(gl), oracle = subsampleGBuffer(g0Read, lc);
    EXPECT_EQ(port.hit.data, oracle.hit.data) << "level " << l;
    EXPECT_EQ(port.depth.data, oracle.depth.data) << "level " << l;
    EXPECT_EQ(port.position.data, oracle.position.data) << "level " << l;
    EXPECT_EQ(port.normal.data, oracle.normal.data) << "level " << l;
    EXPECT_EQ(port.albedo.data, oracle.albedo.data) << "level " << l;
  }
  const EdgeImages port = gpu::detectEdges(scene, g0, f.constants.edges);
  const EdgeImages sameInput = detectEdges(g0Read, f.constants.edges);
  int64_t vsOracle = 0, vsSameInput = 0;
  for (size_t i = 0; i < port.combined.data.size(); ++i) {
    vsOracle += port.combined.data[i] != f.edges.combined.data[i];
    vsSameInput += port.combined.data[i] != sameInput.combined.data[i] || port.normal.data[i] != sameInput.normal.data[i] ||
                   port.depth.data[i] != sameInput.depth.data[i] || port.background.data[i] != sameInput.background.data[i];
  }
  const double pixels = static_cast<double>(port.combined.data.size());
  EXPECT_LE(vsOracle / pixels, kEdges.shareOver);
  EXPECT_LE(vsSameInput / pixels, kEdgesSame.shareOver);
  // Masks: the port's from its own edges against the oracle's from the same edges (exact but
  // for float rounding in the blur), and the stencils against the oracle's end to end.
  const auto portMasks = gpu::buildMasks(scene, port.combined, f.constants);
  const auto oracleSameInput = buildMasks(port.combined, f.constants);
  for (int l = 0; l < kLevelCount; ++l) {
    const MaskLevel &a = portMasks[static_cast<size_t>(l)], &b = oracleSameInput[static_cast<size_t>(l)];
    auto share = [](const ImageU8& x, const ImageU8& y) {
      int64_t n = 0;
      for (size_t i = 0; i < x.data.size(); ++i) n += x.data[i] != y.data[i];
      return static_cast<double>(n) / static_cast<double>(std::max<size_t>(x.data.size(), 1));
    };
    ASSERT_EQ(a.mask.data.size(), b.mask.data.size());
    EXPECT_LE(share(a.mask, b.mask), kMasksSame.shareOver) << "M level " << l;
    if (!f.constants.levels[static_cast<size_t>(l)].enabled) continue;
    EXPECT_LE(share(a.stencil, b.stencil), kMasksSame.shareOver) << "S level " << l;
    float worst = 0.0f;
    for (size_t i = 0; i < a.alpha.data.size(); ++i) worst = std::max(worst, std::fabs(a.alpha.data[i] - b.alpha.data[i]));
    EXPECT_LE(worst, kAlphaSame.pixelThreshold) << "a level " << l;
    int64_t off = 0;
    const ImageU8& oracle = f.levels[static_cast<size_t>(l)].masks.stencil;
    for (size_t i = 0; i < oracle.data.size(); ++i) off += a.stencil.data[i] != oracle.data[i];
    EXPECT_LE(static_cast<double>(off) / static_cast<double>(oracle.data.size()), kStencil.shareOver) << "S level " << l;
  }
  // SSAO with the stencil test, on the port's own G-buffer and the oracle's stencil, against the
  // oracle's SSAO on the same G-buffer: only stencilled pixels are shaded (the rest stay 0).
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = f.constants.levels[static_cast<size_t>(l)];
    gpu::Framebuffer gl(lc.width, lc.height, 3, true);
    gpu::drawLevelGBuffer(scene, f.view, lc, gl);
    const GBuffer g = gpu::readGBuffer(gl);
    const ImageU8& stencil = f.levels[static_cast<size_t>(l)].masks.stencil;
    const ImageF port = gpu::renderSsao(scene, gl, stencil, f.view, lc, f.constants.ssao);
    const ImageF oracle = renderSsao(g, occluderPlanes(g), stencil, f.view, lc, f.constants.ssao);
    int64_t over = 0, shaded = 0;
    double sum2 = 0.0;
    for (size_t i = 0; i < port.data.size(); ++i) {
      if (!stencil.data[i]) {
        ASSERT_EQ(port.data[i], 0.0f) << "level " << l << ": a masked fragment was shaded";
        continue;
      }
      const float d = std::fabs(port.data[i] - oracle.data[i]);
      over += d > kSsaoSame.pixelThreshold;
      sum2 += static_cast<double>(d) * d;
      ++shaded;
    }
    if (shaded == 0) continue;
    EXPECT_LE(static_cast<double>(over) / static_cast<double>(shaded), kSsaoSame.shareOver) << "level " << l;
    EXPECT_LE(std::sqrt(sum2 / static_cast<double>(shaded)), kSsaoSame.rmsBound) << "level " << l;
  }
  RecordProperty("renderer", context_->renderer());
}

TEST(GpuHash, GlslMatchesTheHostBitForBit) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  Scene empty;
  const gpu::GpuScene scene(empty);
  for (int level = 0; level < kLevelCount; ++level) {
    const int w = 1024, h = 512;  // 2^19 inputs per level
    const std::vector<uint32_t> glsl = gpu::hashGrid(scene, w, h, level);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        ASSERT_EQ(glsl[static_cast<size_t>(y) * w + x],
                  pixelHash(static_cast<uint32_t>(x), static_cast<uint32_t>(y), static_cast<uint32_t>(level)))
            << x << "," << y << " level " << level;
  }
}

// The arcade's faceted arches put normal differences near τ_n, where a wrong comparison in the
// edge shader shows; the built-ins have creases far above it and planes far below.
INSTANTIATE_TEST_SUITE_P(Scenes, GpuParity,
                         ::testing::Values("demo", "plane", "slanted", "corner", "steps", "boxes", "fence", "arcade"));

TEST(GpuContext, ReportsTheRendererOrSaysWhyNot) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  EXPECT_FALSE(context.renderer().empty());
  std::cerr << "GL renderer: " << context.renderer() << " via " << context.platform() << "\n";
}

}  // namespace
}  // namespace mrr

namespace mrr {
namespace {

// End to end: the port's final SSAO image against the oracle's, same scene and camera.
TEST(GpuPipeline, SsaoFinalImageMatchesTheOracle) {
  MRR_REQUIRE_GL_OR_SKIP();
  for (Mode mode : {Mode::Mrr, Mode::Full}) {
    const Settings s = test::ssaoSettings(203, 117, 16, mode);
    const auto r = test::renderScene("builtin:demo", s);
    const gpu::GpuRenderer port(*r.scene);
    // The oracle's cost model (as `mrr compare` passes it): the never-slower decision is then the
    // same function of the same stencils on both paths.
    const CostModel costs = CostModel::defaults("cpu");
    const FrameResult g = port.render(r.camera, r.frame.constants, {true, {}, &costs});
    ASSERT_EQ(g.final().data.size(), r.frame.final().data.size());
    double sum2 = 0.0;
    int64_t over = 0;
    for (size_t i = 0; i < g.final().data.size(); ++i) {
      const float d = std::fabs(g.final().data[i] - r.frame.final().data[i]);
      sum2 += static_cast<double>(d) * d;
      over += d > kFinal.pixelThreshold;
    }
    const double n = static_cast<double>(g.final().data.size());
    EXPECT_LE(std::sqrt(sum2 / n), kFinal.rmsBound) << toString(mode);
    EXPECT_LE(static_cast<double>(over) / n, kFinal.shareOver) << toString(mode);
    // Same stencils (up to inherited edge pixels): the ideal speedups agree closely.
    EXPECT_NEAR(g.idealSpeedup, r.frame.idealSpeedup, 0.05 * r.frame.idealSpeedup);
  }
}

}  // namespace
}  // namespace mrr

namespace mrr {
namespace {

// A driver error names the stage and carries the driver's log, on one line.
// A compile error names the file, the variant (its #defines) and the driver's log, on one line;
// not the program's cache key ("planted" here, "blend.final.7.3.covered" in the port), which
// means nothing to a user.
TEST(GpuProgram, CompileErrorNamesTheFileItsVariantAndTheDriversLog) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  const std::string broken = "#version 330 core\nout vec4 c;\nvoid main() { c = undefinedThing; }\n";
  try {
    gpu::compileProgramFromSource("planted.key", "fullscreen.vert", gpu::shaderSource("fullscreen.vert"), "broken.frag",
                                  broken, "#define FINAL_ONLY\n#define COVERED 1\n");
    FAIL() << "a broken shader compiled";
  } catch (const MrrError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find("planted.key"), std::string::npos) << what;
    EXPECT_NE(what.find("broken.frag (variant FINAL_ONLY COVERED) does not compile"), std::string::npos) << what;
    EXPECT_NE(what.find("undefinedThing"), std::string::npos) << what;  // the driver's log
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace mrr

// ---------------------------------------------------------------------------------------------
// SSM and SSGI: the shadow map, its one-tap test, the shadow edges, the SSM and SSGI
// sub-images, each against the oracle's stage end to end and against the oracle's stage run on
// the port's own inputs; then the final image of both effects in both modes.
namespace mrr {
namespace {

// Prints the figures (compare/parity/parity.h, the measure `mrr compare` uses) and checks them against
// a rule of common/tolerance.h with the same verdict `mrr compare` gives (SPEC §8: the
// figures are the result, not only pass/fail).
void expectWithin(const DiffFigures& f, const ToleranceRule& rule, const std::string& what) {
  std::cerr << "[parity] " << what << " (" << rule.stage << "): " << f << "\n";
  EXPECT_TRUE(f.within(rule)) << what << " over " << rule.stage << ": " << f;
}

// The port's shadow map: the light's frame from the shared function, the depths rasterised.
ShadowMap drawPortShadowMap(const gpu::GpuScene& scene, const DirectionalLight& light, int size,
                            const gpu::ShadowMapTarget& target) {
  ShadowMap map = shadowMapFrame(light, scene.bounds(), size);
  gpu::drawShadowMap(scene, map, target);
  map.depth = target.read();
  return map;
}

const ToleranceRule& kMapDepth = tolerance("shadowmap.depth");
const ToleranceRule& kShadowTest = tolerance("shadowtest");
const ToleranceRule& kShadowTestSame = tolerance("shadowtest.same_input");
const ToleranceRule& kSsm = tolerance("ssm");
const ToleranceRule& kSsmSame = tolerance("ssm.same_input");
const ToleranceRule& kDirectSame = tolerance("ssgi.direct.same_input");
const ToleranceRule& kSsgi = tolerance("ssgi");
const ToleranceRule& kSsgiSame = tolerance("ssgi.same_input");

Settings shadowSettings(Effect effect, int w, int h, Mode mode = Mode::Mrr) {
  Settings s = defaultSettings(effect);
  s.width = w;
  s.height = h;
  s.mode = mode;
  s.ssm.samples = 64;  // PCF 8×8
  s.ssm.shadowMapSize = 1024;
  s.ssgi.samples = 48;
  // Stage parity, not the rule's (GpuNeverSlower): near break-even a PCF sample that differs at
  // one of its taps may tip one path's decision and not the other's.
  s.neverSlower = false;
  return s;
}

// A built-in's name, or a shared scene's catalogue name ("cornell", "arcade"), and a size.
struct ShadowCase {
  std::string scene;
  int width, height;
};
void PrintTo(const ShadowCase& c, std::ostream* os) { *os << c.scene << " " << c.width << "x" << c.height; }

class GpuShadowParity : public ::testing::TestWithParam<ShadowCase> {
 protected:
  void SetUp() override {
    MRR_REQUIRE_GL_OR_SKIP();
    const ShadowCase& p = GetParam();
    const std::string file = p.scene == "cornell"  ? "cornell-box/CornellBox-Original.gltf"
                             : p.scene == "arcade" ? "sascha-arcade/subpass_scene_opaque.gltf"
                                                   : "";
    if (!file.empty() && !test::haveSharedScene(file))
      GTEST_SKIP() << "shared scene missing: " << test::sharedScene(file);
    spec_ = file.empty() ? "builtin:" + p.scene : p.scene;
    context_ = std::make_unique<gpu::GlContext>();
  }
  std::string spec_;
  std::unique_ptr<gpu::GlContext> context_;
};

TEST_P(GpuShadowParity, SsmStagesMatchTheOracle) {
  const ShadowCase& p = GetParam();
  // The Cornell box under the built-in default light, as these tolerances were measured: the light
  // chosen for its view (from +z at 30 degrees) flips 24 more shadow-test pixels end to
  // end (same input exact) and its ssm RMS, 0.042, is over the rule's 0.03 (open, see the report).
  const std::optional<glm::vec3> light =
      p.scene == "cornell" ? std::optional<glm::vec3>(-DirectionalLight{}.direction) : std::nullopt;
  const auto r = test::renderScene(spec_, shadowSettings(Effect::Ssm, p.width, p.height), light);
  const FrameResult& f = r.frame;
  const Constants& c = f.constants;
  const gpu::GpuScene scene(*r.scene);
  const std::string name = p.scene + " ssm";

  // 1. The shadow map: the same frame (one shared function), then the depths texel by texel.
  const gpu::ShadowMapTarget mapTarget(c.ssm.shadowMapSize);
  const ShadowMap map = drawPortShadowMap(scene, r.scene->light, c.ssm.shadowMapSize, mapTarget);
  EXPECT_EQ(map.origin, f.shadowMap.origin);
  EXPECT_EQ(map.right, f.shadowMap.right);
  EXPECT_EQ(map.up, f.shadowMap.up);
  EXPECT_EQ(map.forward, f.shadowMap.forward);
  EXPECT_EQ(map.texel, f.shadowMap.texel);
  {
    const DiffFigures fig = diffShadowMaps(map, f.shadowMap, kMapDepth.pixelThreshold);
    ASSERT_GT(fig.pixels, 0) << "nothing in the shadow map";
    expectWithin(fig, kMapDepth, name + " shadow map, covered texels");
  }

  // 2. The one-tap test at full res: on the port's G-buffer and map against the oracle's
  // function on the same inputs, and against the oracle's end to end.
  const LevelConstants& l0 = c.levels[0];
  gpu::Framebuffer g0(l0.width, l0.height, 3, true);
  gpu::drawGBuffer(scene, f.view, g0);
  const GBuffer g0Read = gpu::readGBuffer(g0);
  const gpu::Framebuffer litTarget(l0.width, l0.height, 1, false);
  gpu::drawShadowTest(scene, g0, map, mapTarget.texture(), f.view, c.ssm.biasTexels, litTarget);
  const ImageU8 lit = gpu::readShadowTest(litTarget);
  expectWithin(diffImages(lit, shadowTestImage(g0Read, map, f.view, c.ssm.biasTexels)), kShadowTestSame,
               name + " shadow test, same input");
  expectWithin(diffImages(lit, f.shadowLit), kShadowTest, name + " shadow test vs oracle");

  // 3. Shadow edges: from the port's lit image, against the oracle's edges from the same.
  const EdgeImages edges = gpu::detectEdges(scene, g0, c.edges, litTarget.texture(0));
  const EdgeImages edgesSame = detectEdges(g0Read, c.edges, &lit);
  ASSERT_FALSE(edges.shadow.data.empty());
  expectWithin(diffImages(edges.shadow, edgesSame.shadow), kEdgesSame, name + " shadow edges, same input");
  expectWithin(diffImages(edges.combined, edgesSame.combined), kEdgesSame, name + " E with shadow edges, same input");
  expectWithin(diffImages(edges.shadow, f.edges.shadow), kEdges, name + " shadow edges vs oracle");
  // Not vacuous: where the oracle finds shadow edges the port does too ("shadows" has them).
  EXPECT_EQ(test::countSet(edges.shadow) > 0, test::countSet(f.edges.shadow) > 0);
  if (p.scene == "shadows") EXPECT_GT(test::countSet(edges.shadow), 100) << "the shadow scene without shadow edges";

  // 4. SSM per level with the oracle's stencil: the port on its own G-buffer and map against
  // the oracle's renderSsm on the same (nearly exact), and against the oracle's sub-image.
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    gpu::Framebuffer gl(lc.width, lc.height, 3, true);
    gpu::drawLevelGBuffer(scene, f.view, lc, gl);
    const GBuffer g = gpu::readGBuffer(gl);
    const ImageU8& stencil = f.levels[static_cast<size_t>(l)].masks.stencil;
    const ImageF port = gpu::renderSsm(scene, gl, stencil, map, mapTarget.texture(), f.view, lc, c.ssm);
    for (size_t i = 0; i < port.data.size(); ++i)
      if (!stencil.data[i]) ASSERT_EQ(port.data[i], 0.0f) << "level " << l << ": a masked fragment was shaded";
    const auto shaded = [&](size_t i) { return stencil.data[i] != 0; };
    const std::string L = name + " L" + std::to_string(l);
    if (p.scene == "shadows" && l == 0) {  // not vacuous: the edge band holds umbra and penumbra
      int64_t umbra = 0, penumbra = 0;
      for (size_t i = 0; i < port.data.size(); ++i) {
        umbra += shaded(i) && port.data[i] == 0.0f;
        penumbra += shaded(i) && port.data[i] > 0.0f && port.data[i] < 1.0f;
      }
      EXPECT_GT(umbra, 10);
      EXPECT_GT(penumbra, 40);
    }
    expectWithin(diffImages(port, renderSsm(g, map, stencil, f.view, c.ssm), kSsmSame.pixelThreshold, shaded), kSsmSame,
                 L + " same input");
    expectWithin(diffImages(port, f.levels[static_cast<size_t>(l)].raw, kSsm.pixelThreshold, shaded), kSsm,
                 L + " vs oracle");
  }
}

TEST_P(GpuShadowParity, SsgiStagesMatchTheOracle) {
  const ShadowCase& p = GetParam();
  const auto r = test::renderScene(spec_, shadowSettings(Effect::Ssgi, p.width, p.height));
  const FrameResult& f = r.frame;
  const Constants& c = f.constants;
  const gpu::GpuScene scene(*r.scene);
  const std::string name = p.scene + " ssgi";
  const gpu::ShadowMapTarget mapTarget(c.ssm.shadowMapSize);
  const ShadowMap map = drawPortShadowMap(scene, r.scene->light, c.ssm.shadowMapSize, mapTarget);
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    gpu::Framebuffer gl(lc.width, lc.height, 3, true);
    gpu::drawLevelGBuffer(scene, f.view, lc, gl);
    const GBuffer g = gpu::readGBuffer(gl);
    const std::string L = name + " L" + std::to_string(l);
    // 1. the direct light every pixel sends, against the oracle's on the same G-buffer and map
    const gpu::Framebuffer directTarget(lc.width, lc.height, 1, false);
    gpu::drawDirectLight(scene, gl, map, mapTarget.texture(), f.view, r.scene->light, c.ssm.biasTexels, directTarget);
    const ImageF direct = directTarget.read(0, 3);
    expectWithin(diffImages(direct, directLight(g, map, f.view, r.scene->light, c.ssm.biasTexels),
                         kDirectSame.pixelThreshold, [](size_t) { return true; }),
                 kDirectSame, L + " direct, same input");
    // 2. the gather with the oracle's stencil: against the oracle's on the port's G-buffer and
    // direct light (nearly exact), and against the oracle's sub-image end to end.
    const ImageU8& stencil = f.levels[static_cast<size_t>(l)].masks.stencil;
    const ImageF port = gpu::renderSsgi(scene, gl, directTarget.texture(0), stencil, f.view, lc, c.ssgi);
    for (size_t i = 0; i < stencil.data.size(); ++i)
      if (!stencil.data[i])
        for (int ch = 0; ch < 3; ++ch)
          ASSERT_EQ(port.data[3 * i + static_cast<size_t>(ch)], 0.0f)
              << "level " << l << ": a masked fragment was shaded";
    const auto shaded = [&](size_t i) { return stencil.data[i] != 0; };
    expectWithin(diffImages(port, renderSsgi(g, direct, stencil, f.view, lc, c.ssgi), kSsgiSame.pixelThreshold, shaded),
                 kSsgiSame, L + " same input");
    expectWithin(diffImages(port, f.levels[static_cast<size_t>(l)].raw, kSsgi.pixelThreshold, shaded), kSsgi,
                 L + " vs oracle");
  }
}

// The built-ins made for the effects, the demo, and two shared scenes at 320×180.
INSTANTIATE_TEST_SUITE_P(Scenes, GpuShadowParity,
                         ::testing::Values(ShadowCase{"shadows", 161, 97}, ShadowCase{"redwall", 161, 97},
                                           ShadowCase{"fence", 161, 97},
                                           ShadowCase{"demo", 160, 90}, ShadowCase{"cornell", 320, 180},
                                           ShadowCase{"arcade", 320, 180}),
                         [](const ::testing::TestParamInfo<ShadowCase>& info) { return info.param.scene; });

// The stage names of a frame, less the oracle-only and port-only ones (common/stages.h's kTimed;
// a name not in it is an error).
std::vector<std::string> stageNames(const FrameResult& f) {
  std::vector<std::string> names;
  for (const StageTiming& t : f.timings)
    if (parseTimed(t.stage).info().on == TimedOn::Both) names.push_back(t.stage);
  return names;
}

// End to end: the port's final SSM and SSGI images against the oracle's, both modes, and the
// same stages in the same order in the timings.
TEST(GpuPipeline, SsmAndSsgiFinalImagesMatchTheOracle) {
  MRR_REQUIRE_GL_OR_SKIP();
  for (const auto& [sceneName, effect] : {std::pair{"shadows", Effect::Ssm}, std::pair{"redwall", Effect::Ssgi},
                                          std::pair{"redwall", Effect::Ssm}, std::pair{"shadows", Effect::Ssgi}}) {
    for (Mode mode : {Mode::Mrr, Mode::Full}) {
      const auto r = test::renderScene(std::string("builtin:") + sceneName, shadowSettings(effect, 203, 117, mode));
      const gpu::GpuRenderer port(*r.scene);
      // The oracle's cost model (as `mrr compare` passes it): the never-slower decision is then the
    // same function of the same stencils on both paths.
    const CostModel costs = CostModel::defaults("cpu");
    const FrameResult g = port.render(r.camera, r.frame.constants, {true, {}, &costs});
      const std::string what = std::string(sceneName) + " " + toString(effect) + " " + toString(mode);
      ASSERT_EQ(g.final().data.size(), r.frame.final().data.size()) << what;
      expectWithin(diffImages(g.final(), r.frame.final(), kFinal.pixelThreshold, [](size_t) { return true; }), kFinal,
                   what + " final");
      expectWithin(diffImages(g.shaded, r.frame.shaded, kFinal.pixelThreshold, [](size_t) { return true; }), kFinal,
                   what + " shaded");
      EXPECT_NEAR(g.idealSpeedup, r.frame.idealSpeedup, 0.05 * r.frame.idealSpeedup) << what;
      EXPECT_EQ(stageNames(g), stageNames(r.frame)) << what;
      EXPECT_EQ(g.shadowMap.size, r.frame.constants.ssm.shadowMapSize) << what;
      EXPECT_EQ(g.shadowLit.width, r.frame.shadowLit.width) << what;
    }
  }
}

}  // namespace
}  // namespace mrr

// ---------------------------------------------------------------------------------------------
// The peers (SPEC §9) and the never-slower rule (SPEC §11) on the port: every stage of uniform-1,
// uniform-2 and tiles against the oracle through compareFrames (the check `mrr compare` makes),
// the fallback decided alike on both paths, and planted faults in peers.frag caught at their
// stage.
namespace mrr {
namespace {

// The settings of one peer frame: small odd sizes exercise the padding and the partial tiles.
Settings peerSettings(Effect effect, Mode mode, int w, int h) {
  Settings s = shadowSettings(effect, w, h, mode);
  s.ssao.samples = 16;
  return s;
}

// The stage names of a frame's timings, in order, without the oracle's SSAO "planes.Lℓ" (the
// port's SSAO pass reads the tangent planes from the G-buffer targets directly).

// Renders one frame on both paths from the same constants and cost model.
struct BothPaths {
  test::Rendered oracle;  // the scene, camera and oracle renderer (its frame: no cost model)
  FrameResult cpu, port;
};
BothPaths renderBoth(const std::string& spec, const Settings& s, const CostModel& model) {
  BothPaths b;
  b.oracle = test::renderScene(spec, s);
  const Constants k = makeConstants(s, b.oracle.framedSize);
  // the rule's counts (SSM: its PCF sample) also where the rule is off: both predictions are compared
  b.cpu = b.oracle.renderer->render(b.oracle.camera, k, {true, {}, &model, true});
  const gpu::GpuRenderer port(*b.oracle.scene);
  b.port = port.render(b.oracle.camera, k, {true, {}, &model, true});
  return b;
}

struct PeerCase {
  std::string scene;
  Effect effect;
  Mode mode;
};
void PrintTo(const PeerCase& c, std::ostream* os) {
  *os << c.scene << " " << toString(c.effect) << " " << toString(c.mode);
}

class GpuPeerParity : public ::testing::TestWithParam<PeerCase> {
 protected:
  void SetUp() override {
    MRR_REQUIRE_GL_OR_SKIP();
    context_ = std::make_unique<gpu::GlContext>();
  }
  std::unique_ptr<gpu::GlContext> context_;
};

// The name of an mrr-effect case (its mode is always mrr-effect): scene_effect.
std::string effectCaseName(const ::testing::TestParamInfo<PeerCase>& info) {
  return info.param.scene + "_" + toString(info.param.effect);
}

// Every stage of the peer within its rule: G-buffers, edges, tile rates and stencils, the
// effect, and stage 5 recomputed by the oracle's composePeer from the port's own inputs.
TEST_P(GpuPeerParity, EveryStageMatchesTheOracle) {
  const PeerCase& pc = GetParam();
  const CostModel model = CostModel::defaults("cpu");
  const BothPaths b = renderBoth("builtin:" + pc.scene, peerSettings(pc.effect, pc.mode, 97, 61), model);
  const ParityResult r = compareFrames(b.cpu, b.port, b.oracle.scene->light);
  std::cerr << formatParityTable(r);
  EXPECT_TRUE(r.pass()) << "first failing stage " << r.firstFailing();
  EXPECT_FALSE(b.port.fallback.evaluated) << "the rule is the method's, not the peers'";
  // The same stages in the same order on both paths.
  EXPECT_EQ(stageNames(b.port), stageNames(b.cpu));
  // The rows a peer must have, each computed on the port's own inputs.
  const Constants& c = b.cpu.constants;
  const int k = pc.mode == Mode::Uniform1 ? 1 : 2;
  std::vector<std::string> stages = {"final"};
  if (pc.mode == Mode::Tiles) {
    stages.insert(stages.end(), {"edges", "tilerates", "stencil.L0", "stencil.L1", "stencil.L2", "upsample.L0",
                                 "upsample.L1", "upsample.L2", "composite.L0"});
  } else {
    stages.insert(stages.end(), {"stencil.L0", "stencil.L" + std::to_string(k), "upsample.L" + std::to_string(k),
                                 "blendalpha.L0", "composite.L0"});
    EXPECT_EQ(r.row("raw.L0"), nullptr) << "uniform-k's level 0 shades nothing";
  }
  for (const std::string& stage : stages) {
    const StageRow* row = r.row(stage);
    ASSERT_NE(row, nullptr) << "no row " << stage;
    if (stage != "final") {
      ASSERT_TRUE(row->sameInput) << stage;
    }
  }
  // Stage 3 and the composition's bookkeeping are exact on the same inputs.
  for (const char* exact : {"tilerates", "stencil.L0", "stencil.L1", "stencil.L2", "mask.L0", "mask.L1", "mask.L2",
                            "blendalpha.L0", "blendalpha.L1", "blendalpha.L2"})
    if (const StageRow* row = r.row(exact); row && row->sameInput) {
      EXPECT_EQ(row->sameInput->figures.maxAbs, 0.0) << exact;
    }
  // Not vacuous: the peer shades what it should. uniform-k: every level-k pixel inside W×H
  // and none at level 0; tiles: the levels the rates name.
  const LevelResult& l0 = b.port.levels[0];
  if (pc.mode != Mode::Tiles) {
    EXPECT_EQ(l0.shadedPixels, 0);
    const LevelConstants& lk = c.levels[static_cast<size_t>(k)];
    EXPECT_EQ(b.port.levels[static_cast<size_t>(k)].shadedPixels,
              static_cast<int64_t>((c.width + lk.scale - 1) / lk.scale) * ((c.height + lk.scale - 1) / lk.scale));
    for (uint8_t v : b.port.blend.levelMap.data) ASSERT_EQ(v, k);
  } else {
    ASSERT_EQ(b.port.tileRates.width, (c.paddedWidth + kTileSize - 1) / kTileSize);
    EXPECT_GT(l0.shadedPixels, 0);
  }
  EXPECT_EQ(b.port.shadedPixelsTotal, b.cpu.shadedPixelsTotal);
  RecordProperty("renderer", context_->renderer());
}

std::vector<PeerCase> peerCases() {
  std::vector<PeerCase> cases;
  for (const char* scene : {"demo", "shadows"})
    for (Effect effect : {Effect::Ssao, Effect::Ssm, Effect::Ssgi})
      for (Mode mode : {Mode::Uniform1, Mode::Uniform2, Mode::Tiles}) cases.push_back({scene, effect, mode});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Peers, GpuPeerParity, ::testing::ValuesIn(peerCases()),
                         [](const ::testing::TestParamInfo<PeerCase>& info) {
                           std::string name = info.param.scene + "_" + toString(info.param.effect) + "_" +
                                              toString(info.param.mode);
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

// mrr-effect's masks on both paths (SPEC §12): compare passes, every level's M'_ℓ is exact on
// the port's own inputs.
void expectMasksExact(const ParityResult& r, const std::string& shape) {
  EXPECT_TRUE(r.pass()) << shape << " first failing stage " << r.firstFailing() << "\n" << formatParityTable(r);
  for (int l = 0; l < kLevelCount; ++l) {
    const StageRow* row = r.row("mask.L" + std::to_string(l));
    ASSERT_NE(row, nullptr) << "mask.L" << l;
    ASSERT_TRUE(row->sameInput);
    EXPECT_EQ(row->sameInput->figures.maxAbs, 0.0) << "mask.L" << l << shape;
  }
}

// SPEC §12.3: probe's "why" on each path's own frame: the same reason at every level pixel, and
// covered exactly where the port's own S = 1 (and, for the effect-only arm, never for the
// geometry). Returns how many level pixels the effect covers.
int64_t expectTheSameWhy(const FrameResult& cpu, const FrameResult& port, const std::string& shape, bool noGeometry) {
  const CoverageArms oracleArms = coverageArms(cpu), portArms = coverageArms(port);
  int64_t effect = 0;
  for (int l = 0; l < kLevelCount; ++l) {
    const ImageU8& st = port.levels[static_cast<size_t>(l)].masks.stencil;
    if (st.empty()) continue;
    for (int y = 0; y < st.height; ++y)
      for (int x = 0; x < st.width; ++x) {
        const Coverage o = coverageReason(oracleArms, cpu, l, x, y), p = coverageReason(portArms, port, l, x, y);
        const bool covered = p != Coverage::None && p != Coverage::Limit && p != Coverage::Trim;
        if (o != p || (st.at(x, y) != 0) != covered || (noGeometry && p == Coverage::Geometry)) {
          ADD_FAILURE() << "level " << l << " " << x << "," << y << shape << ": the oracle's why " << coverageName(o)
                        << ", the port's " << coverageName(p) << ", its S " << int(st.at(x, y))
                        << (noGeometry ? " (the effect-only arm has no geometry)" : "");
          return effect;  // one pixel's message, not thousands
        }
        effect += p == Coverage::Effect;
      }
  }
  return effect;
}

// mrr-effect (SPEC §12) on both paths: the footprint's widening (effect_masks.frag) gives the
// oracle's M'_ℓ exactly on the port's own inputs, and every later stage is within its rule. Two
// shapes: the default (from level 1, cap 8) and level 0 widened with a small cap (3), so that
// reaches below the cap, and their rounding, are exercised. Not vacuous: each frame shades more
// than mrr's on the same path.
class GpuEffectMaskParity : public GpuPeerParity {};  // the same GL context per case

TEST_P(GpuEffectMaskParity, WidenedMasksAreExactAndEveryStageMatches) {
  const PeerCase& pc = GetParam();
  const CostModel model = CostModel::defaults("cpu");
  for (const bool fromLevel0 : {false, true}) {
    Settings s = peerSettings(pc.effect, Mode::MrrEffect, 97, 61);
    s.effectMask.trim = false;  // the widening alone (§12.5's trim: GpuTrimParity)
    s.ssm.lightAngle = 0.4f;  // penumbrae wide enough to reach past half a level pixel at 97×61
    if (fromLevel0) {
      s.effectMask.firstLevel = 0;
      s.effectMask.cap = 3;
    }
    const BothPaths b = renderBoth("builtin:" + pc.scene, s, model);
    const std::string shape = fromLevel0 ? " (level 0, cap 3)" : " (default)";
    expectMasksExact(compareFrames(b.cpu, b.port, b.oracle.scene->light), shape);
    // SPEC §12.3: probe's "why" agrees on both paths; some pixel is there for the effect.
    const int64_t effect = expectTheSameWhy(b.cpu, b.port, shape, false);
    EXPECT_GT(effect, 0) << "no pixel covered for the effect" << (fromLevel0 ? " (level 0, cap 3)" : "");
    s.mode = Mode::Mrr;
    const BothPaths paper = renderBoth("builtin:" + pc.scene, s, model);
    int64_t widened = 0, edges = 0;  // M'_ℓ against mrr's M_ℓ, summed over the levels
    for (int l = 0; l < kLevelCount; ++l) {
      for (uint8_t v : b.port.levels[static_cast<size_t>(l)].masks.mask.data) widened += v;
      for (uint8_t v : paper.port.levels[static_cast<size_t>(l)].masks.mask.data) edges += v;
    }
    EXPECT_GT(widened, edges) << "the widening widened nothing" << (fromLevel0 ? " (level 0, cap 3)" : "");
    EXPECT_GE(b.port.shadedPixelsTotal, paper.port.shadedPixelsTotal);
    EXPECT_EQ(b.port.shadedPixelsTotal, b.cpu.shadedPixelsTotal);
  }
}

INSTANTIATE_TEST_SUITE_P(Effects, GpuEffectMaskParity,
                         ::testing::Values(PeerCase{"demo", Effect::Ssao, Mode::MrrEffect},
                                           PeerCase{"shadows", Effect::Ssm, Mode::MrrEffect},
                                           PeerCase{"demo", Effect::Ssgi, Mode::MrrEffect}),
                         effectCaseName);

// The ablation's effect-only arm (SPEC §12.3, --effect-only, bench variant +e) on both paths:
// effect_masks.frag STEP 4 gives the oracle's M'_ℓ ∧ ¬M_ℓ exactly on the port's own inputs, a
// level below ℓ_first holds nothing, and every later stage is within its rule. Two shapes, as
// GpuEffectMaskParity: the default (from level 1, so level 0 is empty) and level 0 widened with
// cap 3. On the port's own frames, level by level before the blur: effect only ∧ geometry only
// = ∅ and effect only ∨ geometry only = both (mrr and mrr-effect). Not vacuous: some level keeps a
// ring, and with level 0 empty the arm shades fewer pixels than both.
class GpuEffectOnlyParity : public GpuPeerParity {};  // the same GL context per case

// The settings of an effect-only frame: SSM's penumbrae wide enough to reach past half a level
// pixel at 97×61 (as GpuEffectMaskParity).
Settings effectOnlySettings(Effect effect, bool fromLevel0) {
  Settings s = peerSettings(effect, Mode::MrrEffect, 97, 61);
  s.effectMask.trim = false;  // the arms before §12.5's trim, which cuts what the blend never reads
  s.ssm.lightAngle = 0.4f;
  s.effectMask.effectOnly = true;
  s.effectMask.budget = 0.0f;  // the ablation's arms are a priori
  if (fromLevel0) {
    s.effectMask.firstLevel = 0;
    s.effectMask.cap = 3;
  }
  return s;
}

TEST_P(GpuEffectOnlyParity, TheWideningAloneIsExactAndEveryStageMatches) {
  const PeerCase& pc = GetParam();
  const CostModel model = CostModel::defaults("cpu");
  for (const bool fromLevel0 : {false, true}) {
    const std::string shape = fromLevel0 ? " (level 0, cap 3)" : " (default)";
    Settings s = effectOnlySettings(pc.effect, fromLevel0);
    const BothPaths b = renderBoth("builtin:" + pc.scene, s, model);
    expectMasksExact(compareFrames(b.cpu, b.port, b.oracle.scene->light), shape);
    EXPECT_EQ(b.port.shadedPixelsTotal, b.cpu.shadedPixelsTotal) << shape;
    // probe's "why" agrees on both paths; no pixel is there for the geometry (the arm has none).
    const int64_t effect = expectTheSameWhy(b.cpu, b.port, shape, true);
    EXPECT_GT(effect, 0) << "no pixel covered for the effect" << shape;
    // The arms on the port, from the same scene and camera: both (mrr-effect) and geometry only (mrr).
    const gpu::GpuRenderer port(*b.oracle.scene);
    s.effectMask.effectOnly = false;
    const FrameResult both = port.render(b.oracle.camera, makeConstants(s, b.oracle.framedSize), {true, {}, &model, true});
    s.mode = Mode::Mrr;
    const FrameResult geometry =
        port.render(b.oracle.camera, makeConstants(s, b.oracle.framedSize), {true, {}, &model, true});
    const Constants& c = b.port.constants;
    int64_t ring = 0;
    for (int l = 0; l < kLevelCount; ++l) {
      const size_t li = static_cast<size_t>(l);
      if (!c.levels[li].enabled) continue;
      const ImageU8 &only = b.port.levels[li].masks.mask, &m = geometry.levels[li].masks.mask,
                    &wide = both.levels[li].masks.mask;
      ASSERT_EQ(only.data.size(), m.data.size()) << "level " << l;
      ASSERT_EQ(only.data.size(), wide.data.size()) << "level " << l;
      const bool coarsest = l == c.coarsestEnabled, below = l < c.effectMask.firstLevel && !coarsest;
      for (size_t i = 0; i < only.data.size(); ++i) {
        if (coarsest) {  // unchanged: a ≡ 1
          ASSERT_EQ(only.data[i], m.data[i]) << "coarsest level " << l << " pixel " << i << shape;
          continue;
        }
        if (below) {
          ASSERT_EQ(only.data[i], 0) << "level " << l << " below the first widened, pixel " << i << shape;
          continue;
        }
        ASSERT_FALSE(only.data[i] && m.data[i]) << "level " << l << " pixel " << i << ": effect only keeps an edge" << shape;
        ASSERT_EQ(only.data[i] || m.data[i], wide.data[i] != 0)
            << "level " << l << " pixel " << i << ": effect only ∨ geometry only ≠ both" << shape;
        ring += only.data[i];
      }
    }
    EXPECT_GT(ring, 0) << "no level kept a ring: the check is vacuous" << shape;
    // Never more than both; fewer where level 0 is empty (from level 0, cap 3, the blur of SSAO's
    // ring can cover the edges it surrounds: as many pixels as both on demo and shadows).
    EXPECT_LE(b.port.shadedPixelsTotal, both.shadedPixelsTotal) << shape;
    if (!fromLevel0) EXPECT_LT(b.port.shadedPixelsTotal, both.shadedPixelsTotal) << shape;
  }
}

INSTANTIATE_TEST_SUITE_P(Effects, GpuEffectOnlyParity,
                         ::testing::Values(PeerCase{"demo", Effect::Ssao, Mode::MrrEffect},
                                           PeerCase{"demo", Effect::Ssm, Mode::MrrEffect},
                                           PeerCase{"shadows", Effect::Ssao, Mode::MrrEffect},
                                           PeerCase{"shadows", Effect::Ssm, Mode::MrrEffect}),
                         effectCaseName);

// mrr-effect's a-posteriori term (SPEC §12.2) on both paths: refinement_marks.frag gives the
// oracle's marks exactly from the port's own coarser result, stencil and G-buffer, and
// refine_masks.frag (with masks.frag's blur) the oracle's refined M_ℓ, a_ℓ and S_ℓ from the port's
// own marks; every stage is within its rule. Not vacuous: the port marks pixels at every level it
// refines, and its refined frame shades more than its a priori one.
class GpuPosteriorParity : public GpuPeerParity {};  // the same GL context per case

// τ_v per effect: small enough that each effect marks pixels on these frames at 97×61.
float posteriorTau(Effect effect) { return effect == Effect::Ssgi ? 0.02f : 0.05f; }

TEST_P(GpuPosteriorParity, MarksAndRefinedMasksAreExactAndEveryStageMatches) {
  const PeerCase& pc = GetParam();
  const CostModel model = CostModel::defaults("cpu");
  Settings s = peerSettings(pc.effect, Mode::MrrEffect, 97, 61);
  s.effectMask.trim = false;  // §12.2 alone: the trim keeps a coarser level only where it is read (GpuTrimParity)
  s.ssm.lightAngle = 0.4f;
  s.effectMask.cap = 4;
  s.effectMask.budget = 0.0f;  // a priori, then τ_v's marks (SPEC §12.4's budget: GpuEffectBudget)
  const BothPaths prior = renderBoth("builtin:" + pc.scene, s, model);
  s.effectMask.posterior = posteriorTau(pc.effect);
  const BothPaths b = renderBoth("builtin:" + pc.scene, s, model);
  const ParityResult r = compareFrames(b.cpu, b.port, b.oracle.scene->light);
  EXPECT_TRUE(r.pass()) << "first failing stage " << r.firstFailing() << "\n" << formatParityTable(r);
  const Constants& c = b.port.constants;
  for (int l = 0; l < kLevelCount; ++l) {
    const std::string L = ".L" + std::to_string(l);
    const StageRow* marks = r.row("marks" + L);
    if (!c.levels[static_cast<size_t>(l)].enabled) continue;  // SSGI's level 1 (the paper's Table 1)
    if (l == c.coarsestEnabled) {
      EXPECT_EQ(marks, nullptr) << "the coarsest level is shaded first, never refined";
      continue;
    }
    ASSERT_NE(marks, nullptr) << "marks" << L << "\n" << formatParityTable(r);
    ASSERT_TRUE(marks->sameInput);
    EXPECT_EQ(marks->sameInput->figures.maxAbs, 0.0) << "marks" << L;
    int64_t marked = 0;
    for (uint8_t v : b.port.levels[static_cast<size_t>(l)].marks.data) marked += v;
    EXPECT_GT(marked, 0) << "marks" << L << ": nothing marked, the check would be vacuous";
    for (const std::string part : {"mask", "stencil"}) {
      const StageRow* row = r.row(part + L);
      ASSERT_NE(row, nullptr) << part << L;
      ASSERT_TRUE(row->sameInput);
      EXPECT_EQ(row->sameInput->figures.maxAbs, 0.0) << part << L;
    }
    const StageRow* alpha = r.row("alpha" + L);
    ASSERT_NE(alpha, nullptr);
    EXPECT_LE(alpha->sameInput->figures.maxAbs, 1e-6) << "alpha" << L;
  }
  EXPECT_GT(b.port.shadedPixelsTotal, prior.port.shadedPixelsTotal) << "the refinement shaded nothing more";
  EXPECT_GT(b.cpu.shadedPixelsTotal, prior.cpu.shadedPixelsTotal);
}

// mrr-effect's trim (SPEC §12.5) on both paths: blend.frag REACH and trim.frag give the oracle's
// trimmed S_ℓ exactly on the port's own inputs, a priori and with the budget's refinement (which
// keeps S_ℓ ⊆ D_ℓ), and every stage is within its rule. Not vacuous: the port shades fewer
// pixels than without the trim, as many as the oracle.
class GpuTrimParity : public GpuPeerParity {};  // the same GL context per case

TEST_P(GpuTrimParity, TrimmedStencilsAreExactAndEveryStageMatches) {
  const PeerCase& pc = GetParam();
  const CostModel model = CostModel::defaults("cpu");
  for (const float budget : {0.0f, 0.85f}) {
    Settings s = peerSettings(pc.effect, Mode::MrrEffect, 97, 61);
    s.effectMask.trim = false;
    s.ssm.lightAngle = 0.4f;
    s.effectMask.budget = budget;
    const BothPaths whole = renderBoth("builtin:" + pc.scene, s, model);
    s.effectMask.trim = true;
    const BothPaths b = renderBoth("builtin:" + pc.scene, s, model);
    const std::string shape = budget > 0.0f ? " (budget)" : " (a priori)";
    const ParityResult r = compareFrames(b.cpu, b.port, b.oracle.scene->light);
    EXPECT_TRUE(r.pass()) << shape << " first failing stage " << r.firstFailing() << "\n" << formatParityTable(r);
    for (int l = 1; l < kLevelCount; ++l) {
      if (!b.port.constants.levels[static_cast<size_t>(l)].enabled) continue;
      const StageRow* row = r.row("stencil.L" + std::to_string(l));
      ASSERT_NE(row, nullptr) << "stencil.L" << l;
      ASSERT_TRUE(row->sameInput);
      EXPECT_EQ(row->sameInput->figures.maxAbs, 0.0) << "stencil.L" << l << shape;
    }
    EXPECT_LT(b.port.shadedPixelsTotal, whole.port.shadedPixelsTotal) << shape << ": the trim cut nothing";
    EXPECT_EQ(b.port.shadedPixelsTotal, b.cpu.shadedPixelsTotal) << shape;
    if (budget == 0.0f) EXPECT_EQ(b.port.blend.final.data, whole.port.blend.final.data) << "the blend reads nothing it cut";
  }
}

INSTANTIATE_TEST_SUITE_P(Effects, GpuTrimParity,
                         ::testing::Values(PeerCase{"demo", Effect::Ssao, Mode::MrrEffect},
                                           PeerCase{"shadows", Effect::Ssm, Mode::MrrEffect},
                                           PeerCase{"demo", Effect::Ssgi, Mode::MrrEffect}),
                         effectCaseName);

// With SPEC §13's level limit (a gaze), the port limits its marks as the oracle does (masks.frag
// STEP 5 on the marks, applyLevelLimit on the oracle's): exact on the port's own inputs, and the
// limit clears marks the unlimited frame has.
TEST(GpuPosteriorLimit, MarksObeyTheLevelLimitExactly) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const CostModel model = CostModel::defaults("cpu");
  Settings s = peerSettings(Effect::Ssao, Mode::MrrEffect, 160, 90);
  s.effectMask.cap = 4;
  s.effectMask.posterior = posteriorTau(Effect::Ssao);
  const BothPaths free = renderBoth("builtin:demo", s, model);
  s.foveation.gaze = true;
  s.foveation.gazeX = 30;
  s.foveation.gazeY = 20;
  s.foveation.ppd = 150.0f;  // level 1 allowed from a few pixels out: most of level 0's marks are cleared
  const BothPaths b = renderBoth("builtin:demo", s, model);
  const ParityResult r = compareFrames(b.cpu, b.port, b.oracle.scene->light);
  EXPECT_TRUE(r.pass()) << "first failing stage " << r.firstFailing() << "\n" << formatParityTable(r);
  const StageRow* marks = r.row("marks.L0");
  ASSERT_NE(marks, nullptr);
  ASSERT_TRUE(marks->sameInput);
  EXPECT_EQ(marks->sameInput->figures.maxAbs, 0.0);
  int64_t limited = 0, unlimited = 0;
  for (uint8_t v : b.port.levels[0].marks.data) limited += v;
  for (uint8_t v : free.port.levels[0].marks.data) unlimited += v;
  EXPECT_GT(unlimited, 0);
  EXPECT_LT(limited, unlimited) << "the limit cleared no mark";
}

INSTANTIATE_TEST_SUITE_P(Effects, GpuPosteriorParity,
                         ::testing::Values(PeerCase{"demo", Effect::Ssao, Mode::MrrEffect},
                                           PeerCase{"shadows", Effect::Ssm, Mode::MrrEffect},
                                           PeerCase{"demo", Effect::Ssgi, Mode::MrrEffect}),
                         effectCaseName);

// SPEC §11 on both paths: a cost model whose blend costs more than any saving makes both fall
// back to full, the same frame; one whose overhead is free makes neither fall back. The
// decision is the same function (common/cost_model.h) of the same stencils on both.
TEST(GpuNeverSlower, BothPathsDecideAlikeAndRenderTheSameFrame) {
  MRR_REQUIRE_GL_OR_SKIP();
  for (Effect effect : {Effect::Ssao, Effect::Ssm}) {
    for (const bool expensive : {true, false}) {
      CostModel model = CostModel::defaults("cpu");
      model.source = expensive ? "test: blend 1 s per pixel" : "test: free overhead";
      model.nsPerBlendPixel = expensive ? 1e9 : 0.0;
      if (!expensive) {  // nothing but shading costs, and a stencilled pixel no more than a dense one
        model.nsPerCoarseGbufferPixel = model.nsPerFineBlendPixel = 0.0;
        model.nsPerEdgePixel = model.nsPerMaskPixel = model.edgesMasksFixedMs = 0.0;
        for (EffectCost& e : model.effect) {
          e.sparseFactor = 1.0;
          e.fixedMs = 0.0;
        }
      }
      Settings s = peerSettings(effect, Mode::Mrr, 97, 61);
      s.neverSlower = true;
      const BothPaths b = renderBoth("builtin:demo", s, model);
      const std::string what = toString(effect) + (expensive ? " expensive blend" : " free overhead");
      ASSERT_TRUE(b.cpu.fallback.evaluated && b.port.fallback.evaluated) << what;
      EXPECT_EQ(b.cpu.fallback.fellBack, expensive) << what;
      EXPECT_EQ(b.port.fallback.fellBack, expensive) << what;
      EXPECT_EQ(b.port.fallback.costModel, model.source) << what;
      // Full's prediction depends on the constants alone; the method's on the stencil counts.
      EXPECT_EQ(b.port.fallback.predictedFullMs, b.cpu.fallback.predictedFullMs) << what;
      EXPECT_NEAR(b.port.fallback.predictedMrrMs, b.cpu.fallback.predictedMrrMs,
                  1e-3 * b.cpu.fallback.predictedMrrMs)
          << what;
      for (int l = 1; l < kLevelCount; ++l)
        EXPECT_EQ(b.port.constants.levels[static_cast<size_t>(l)].enabled, !expensive && b.cpu.constants.levels[static_cast<size_t>(l)].enabled) << what;
      EXPECT_EQ(b.port.shadedPixelsTotal, expensive ? int64_t{97} * 61 : b.cpu.shadedPixelsTotal) << what;
      const ParityResult r = compareFrames(b.cpu, b.port, b.oracle.scene->light);
      EXPECT_TRUE(r.pass()) << what << "\n" << formatParityTable(r);
      const StageRow* row = r.row("fallback");
      ASSERT_NE(row, nullptr) << what;
      EXPECT_EQ(row->verdict(), "PASS") << what;
      EXPECT_EQ(stageNames(b.port), stageNames(b.cpu)) << what;
    }
  }
}

// SPEC §11's H_a and H_p: where the model prices PCF (e > 0), the port asks its own PCSS
// (ssm.frag with PCF_SAMPLE) what it pays at the same one pixel in 8×8, and the two samples agree
// but for taps on the knife's edge of a blocker test.
TEST(GpuNeverSlower, ThePortSamplesWherePcfRunsAsTheOracleDoes) {
  MRR_REQUIRE_GL_OR_SKIP();
  const CostModel model = CostModel::defaults("cpu");
  ASSERT_GT(model.effect[static_cast<size_t>(Effect::Ssm)].nsPerPcfSample, 0.0);
  Settings s = peerSettings(Effect::Ssm, Mode::Mrr, 203, 149);
  s.neverSlower = false;
  const BothPaths b = renderBoth("builtin:shadows", s, model);
  ASSERT_EQ(b.cpu.pcfSample.width, 26);
  ASSERT_EQ(b.cpu.pcfSample.height, 19);
  ASSERT_EQ(b.port.pcfSample.width, b.cpu.pcfSample.width);
  ASSERT_EQ(b.port.pcfSample.height, b.cpu.pcfSample.height);
  int pays = 0, searchOnly = 0, differ = 0, footprintOff = 0, withFootprint = 0;
  for (size_t i = 0; i < b.cpu.pcfSample.data.size(); ++i) {
    const uint8_t cpu = b.cpu.pcfSample.data[i], port = b.port.pcfSample.data[i];
    pays += pcfSampleClass(cpu) == kPcfSamplePcf;
    searchOnly += pcfSampleClass(cpu) == kPcfSampleSearch;
    differ += pcfSampleClass(cpu) != pcfSampleClass(port);
    // the footprint (SPEC §11), from each path's own G-buffer: the same steps but where it rounds
    footprintOff += std::abs(pcfSampleFootprintSteps(cpu) - pcfSampleFootprintSteps(port)) > 1;
    withFootprint += pcfSampleFootprintSteps(cpu) > 0;
  }
  EXPECT_GT(pays, 10) << "the scene's slabs cast shadows the search finds";
  EXPECT_GT(searchOnly, 10) << "and open ground it does not";
  EXPECT_GT(withFootprint, 100) << "every searching sample on geometry has neighbours some texels apart";
  EXPECT_LE(differ, 2) << "of " << b.cpu.pcfSample.data.size() << " samples";
  EXPECT_LE(footprintOff, 2) << "of " << b.cpu.pcfSample.data.size() << " samples";
  EXPECT_GT(b.port.counts.pcfPixels, 0);
  const double counts = tolerance("rule.pcf_counts").shareOver;
  EXPECT_NEAR(static_cast<double>(b.port.counts.pcfPixels), static_cast<double>(b.cpu.counts.pcfPixels),
              counts * static_cast<double>(b.cpu.counts.pcfPixels));
  EXPECT_NEAR(static_cast<double>(b.port.counts.searchedPixels), static_cast<double>(b.cpu.counts.searchedPixels),
              counts * static_cast<double>(b.cpu.counts.searchedPixels));
  ASSERT_GT(b.cpu.counts.searchedFootprint, 0);
  EXPECT_NEAR(static_cast<double>(b.port.counts.searchedFootprint), static_cast<double>(b.cpu.counts.searchedFootprint),
              counts * static_cast<double>(b.cpu.counts.searchedFootprint));
  // The port's own model prices PCF as well; a model that does not (e = 0) never draws the sample.
  const gpu::GpuRenderer port(*b.oracle.scene);
  const Constants k = makeConstants(s, b.oracle.framedSize);
  const CostModel portModel = CostModel::defaults("gpu");
  ASSERT_GT(portModel.effect[static_cast<size_t>(Effect::Ssm)].nsPerPcfSample, 0.0);
  // (frames that keep their stages: the resident frame keeps its sample on the GPU)
  const FrameResult own = port.render(b.oracle.camera, k, {true, {}, &portModel, true});
  EXPECT_EQ(own.pcfSample.data, b.port.pcfSample.data);
  CostModel blind = portModel;
  blind.effect[static_cast<size_t>(Effect::Ssm)].nsPerPcfSample = 0.0;
  const FrameResult unsampled = port.render(b.oracle.camera, k, {true, {}, &blind, true});
  EXPECT_TRUE(unsampled.pcfSample.empty());
  EXPECT_EQ(unsampled.counts.pcfPixels, 0);
  // With the rule off, a frame whose caller does not read the rule's counts pays no sample; with
  // it on, the sample is drawn whatever the caller asks.
  ASSERT_FALSE(k.neverSlower);
  EXPECT_TRUE(port.render(b.oracle.camera, k, {true, {}, &portModel}).pcfSample.empty());
  Constants on = k;
  on.neverSlower = true;
  EXPECT_EQ(port.render(b.oracle.camera, on, {true, {}, &portModel}).pcfSample.data, b.port.pcfSample.data);
  // the resident frame counts the same sample on the GPU
  EXPECT_EQ(port.render(b.oracle.camera, k, {false, {}, &portModel, true}).counts.pcfPixels, own.counts.pcfPixels);
}

// The edge sample (SPEC §11): edges.frag with EDGE_SAMPLE against the oracle's edgeSample on the
// port's own G-buffer (and SSM's shadow test), block for block but for the edge image's own
// same-input tolerance; and end to end, the port's frame's sample and its counts against the
// oracle's frame's.
TEST(GpuNeverSlower, ThePortSamplesEdgesAsTheOracleDoes) {
  MRR_REQUIRE_GL_OR_SKIP();
  for (const Effect effect : {Effect::Ssao, Effect::Ssm}) {
    Settings s = peerSettings(effect, Mode::Mrr, 203, 149);
    s.neverSlower = false;
    const BothPaths b = renderBoth("builtin:shadows", s, CostModel::defaults("cpu"));
    const Constants& c = b.cpu.constants;
    ASSERT_EQ(b.cpu.edgeSample.width, 26);
    ASSERT_EQ(b.cpu.edgeSample.height, 19);
    ASSERT_EQ(b.port.edgeSample.width, b.cpu.edgeSample.width);
    ASSERT_EQ(b.port.edgeSample.height, b.cpu.edgeSample.height);
    const double blocks = static_cast<double>(b.cpu.edgeSample.data.size());
    const gpu::GlContext context;
    const gpu::GpuScene scene(*b.oracle.scene);
    gpu::Framebuffer g0(c.levels[0].width, c.levels[0].height, 3, true);
    gpu::drawGBuffer(scene, b.cpu.view, g0);
    const GBuffer g0Read = gpu::readGBuffer(g0);
    ImageU8 lit;
    std::unique_ptr<gpu::ShadowMapTarget> mapTarget;
    std::unique_ptr<gpu::Framebuffer> litTarget;
    if (effect == Effect::Ssm) {
      mapTarget = std::make_unique<gpu::ShadowMapTarget>(c.ssm.shadowMapSize);
      const ShadowMap map = drawPortShadowMap(scene, b.oracle.scene->light, c.ssm.shadowMapSize, *mapTarget);
      litTarget = std::make_unique<gpu::Framebuffer>(c.levels[0].width, c.levels[0].height, 1, false);
      gpu::drawShadowTest(scene, g0, map, mapTarget->texture(), b.cpu.view, c.ssm.biasTexels, *litTarget);
      lit = gpu::readShadowTest(*litTarget);
    }
    const ImageU8 port = gpu::readEdgeSample(*gpu::drawEdgeSample(scene, g0, c.edges, litTarget ? litTarget->texture(0) : 0));
    const ImageU8 same = edgeSample(g0Read, c.edges, lit.empty() ? nullptr : &lit);
    int64_t sameDiffer = 0, endToEndDiffer = 0, sampled = 0;
    for (size_t i = 0; i < same.data.size(); ++i) {
      sameDiffer += port.data[i] != same.data[i];
      endToEndDiffer += b.port.edgeSample.data[i] != b.cpu.edgeSample.data[i];
      sampled += same.data[i];
    }
    const std::string name = toString(effect);
    EXPECT_GT(sampled, 20) << name << ": the slabs' silhouettes and creases are sampled";
    EXPECT_LT(sampled, static_cast<int64_t>(blocks)) << name << ": and the open ground is not";
    // a block is the OR of E at 8 pixels: the edges' share of differing pixels, at most 8 times over
    EXPECT_LE(sameDiffer / blocks, kEdgesSame.shareOver * kEdgeSampleStep) << name << ", same input";
    EXPECT_LE(endToEndDiffer / blocks, kEdges.shareOver * kEdgeSampleStep) << name << ", end to end";
    EXPECT_NEAR(static_cast<double>(b.port.counts.reach[0]), static_cast<double>(b.cpu.counts.reach[0]),
                tolerance("rule.reach").shareOver * static_cast<double>(b.cpu.counts.reach[0]))
        << name;
  }
}

// A decision that differs stops the comparison at the "fallback" row: the frames have
// different levels from there on.
TEST(GpuNeverSlower, ADifferentDecisionFailsAtTheFallbackRow) {
  MRR_REQUIRE_GL_OR_SKIP();
  CostModel fallsBack = CostModel::defaults("cpu"), staysMultires = fallsBack;
  fallsBack.nsPerBlendPixel = 1e9;
  staysMultires.nsPerBlendPixel = staysMultires.nsPerFineBlendPixel = staysMultires.nsPerCoarseGbufferPixel = 0.0;
  staysMultires.nsPerEdgePixel = staysMultires.nsPerMaskPixel = 0.0;
  staysMultires.edgesMasksFixedMs = 0.0;
  for (EffectCost& e : staysMultires.effect) {
    e.sparseFactor = 1.0;
    e.fixedMs = 0.0;
  }
  Settings s = peerSettings(Effect::Ssao, Mode::Mrr, 97, 61);
  s.neverSlower = true;
  const auto r = test::renderScene("builtin:demo", s);
  const Constants k = makeConstants(s, r.framedSize);
  const FrameResult cpu = r.renderer->render(r.camera, k, {true, {}, &staysMultires});
  const gpu::GpuRenderer port(*r.scene);
  const FrameResult gpu = port.render(r.camera, k, {true, {}, &fallsBack});
  const ParityResult result = compareFrames(cpu, gpu, r.scene->light);
  EXPECT_EQ(result.firstFailing(), "fallback");
  EXPECT_EQ(result.rows.back().stage, "fallback");
}

// Sets MRR_GPU_FAULT for one scope (gpu/faults.h): renderers made inside it compile the
// patched shader.
struct PlantedFaultScope {
  explicit PlantedFaultScope(const std::string& name) { setenv("MRR_GPU_FAULT", name.c_str(), 1); }
  ~PlantedFaultScope() { unsetenv("MRR_GPU_FAULT"); }
  PlantedFaultScope(const PlantedFaultScope&) = delete;
  PlantedFaultScope& operator=(const PlantedFaultScope&) = delete;
};

// The oracle's frame `cpu` (of `r`'s scene and camera with constants k) against the port's, clean
// and then with `fault` planted: the clean frame passes, the faulty one fails first at the stage
// the fault catalogue names (`label` prefixes the messages).
void expectCaughtAt(const test::Rendered& r, const Constants& k, const CostModel& model, const FrameResult& cpu,
                    const gpu::ShaderFault& fault, const std::string& label) {
  {
    const gpu::GpuRenderer clean(*r.scene);
    const ParityResult ok = compareFrames(cpu, clean.render(r.camera, k, {true, {}, &model}), r.scene->light);
    EXPECT_TRUE(ok.pass()) << label << "without the fault\n" << formatParityTable(ok);
  }
  const PlantedFaultScope planted(fault.name);
  const gpu::GpuRenderer faulty(*r.scene);
  const ParityResult bad = compareFrames(cpu, faulty.render(r.camera, k, {true, {}, &model}), r.scene->light);
  EXPECT_FALSE(bad.pass()) << label;
  EXPECT_EQ(bad.firstFailing().rfind(fault.stage, 0), 0u)
      << label << "first failing stage " << bad.firstFailing() << ", expected " << fault.stage << "\n"
      << formatParityTable(bad);
}

// Each planted fault in peers.frag makes compareFrames fail, first at the stage the fault
// catalogue names for it; the same frame without the fault passes.
TEST(GpuPeerFaults, ComparisonFailsAtTheStageWhereTheBugIs) {
  MRR_REQUIRE_GL_OR_SKIP();
  struct Case {
    std::string fault;
    Mode mode;
    std::string scene;
  };
  // tiles-no-dilation needs tiles beside an edge tile (rate 1), which it turns into rate 2:
  // the staircase's treads and risers have plain tiles between their creases (at 161×97 the
  // fault moves 36% of the 77 tiles). jbu-no-depth: without the depth term the taps of one
  // surface weigh alike whatever their depth (the demo at 161×97: ĉ_k off by up to 0.08 on
  // 20% of pixels).
  for (const Case& fc : {Case{"tiles-no-dilation", Mode::Tiles, "steps"}, Case{"jbu-no-depth", Mode::Uniform2, "demo"},
                         Case{"jbu-no-depth", Mode::Uniform1, "demo"}}) {
    const gpu::ShaderFault* fault = nullptr;
    for (const gpu::ShaderFault& f : gpu::shaderFaults())
      if (f.name == fc.fault) fault = &f;
    ASSERT_NE(fault, nullptr) << fc.fault;
    const Settings s = peerSettings(Effect::Ssao, fc.mode, 161, 97);
    const CostModel model = CostModel::defaults("cpu");
    const auto r = test::renderScene("builtin:" + fc.scene, s);
    const Constants k = makeConstants(s, r.framedSize);
    const FrameResult cpu = r.renderer->render(r.camera, k, {true, {}, &model});
    expectCaughtAt(r, k, model, cpu, *fault, fc.fault + ": ");
  }
}

// The a-posteriori term's planted faults (SPEC §12.2): each makes compareFrames fail first at the
// stage the catalogue names, and the same frame without the fault passes. marks-inclusive (>= for
// >) differs only where a 3×3 range equals τ_v exactly: τ_v is taken from the port's own clean
// frame, the commonest non-zero range of the coarsest level's result (SSM's PCF fractions k/N
// repeat exactly), so the fault has pixels to mark. refine-stencil-replaced drops what the closure
// gave S_ℓ: with level 1 unblurred (σ_1² = 0) and not widened, S_1 = M_1 ∨ marks, and the closure's
// max-pool of S_0 (blurred r_0 = 3 full-res pixels past E) reaches past it.
namespace {
// The 3×3 ranges of `c` over shaded hit pixels (refinementMarks' v, SPEC §12.2 step 1), each count.
std::map<float, int> rangeCounts(const LevelResult& level) {
  std::map<float, int> counts;
  const ImageF& c = level.sub;
  const auto shaded = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < c.width && y < c.height && level.masks.stencil.at(x, y) && level.gbuffer.hit.at(x, y);
  };
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      if (!shaded(x, y)) continue;
      float range = 0.0f;
      for (int ch = 0; ch < c.channels; ++ch) {
        float lo = c.at(x, y, ch), hi = lo;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            if (shaded(x + dx, y + dy)) {
              lo = std::min(lo, c.at(x + dx, y + dy, ch));
              hi = std::max(hi, c.at(x + dx, y + dy, ch));
            }
        range = std::max(range, hi - lo);
      }
      if (range > 0.0f) ++counts[range];
    }
  return counts;
}
}  // namespace

TEST(GpuPosteriorFaults, ComparisonFailsAtTheStageWhereTheBugIs) {
  MRR_REQUIRE_GL_OR_SKIP();
  struct Case {
    std::string fault;
    Effect effect;
    std::string scene;
  };
  for (const Case& fc : {Case{"marks-2x2", Effect::Ssao, "demo"}, Case{"marks-inclusive", Effect::Ssm, "shadows"},
                         Case{"refine-marks-dropped", Effect::Ssao, "demo"},
                         Case{"refine-stencil-replaced", Effect::Ssao, "demo"},
                         Case{"budget-key-octaves", Effect::Ssao, "demo"},
                         Case{"budget-last-round-skipped", Effect::Ssgi, "demo"}}) {
    const gpu::ShaderFault* fault = nullptr;
    for (const gpu::ShaderFault& f : gpu::shaderFaults())
      if (f.name == fc.fault) fault = &f;
    ASSERT_NE(fault, nullptr) << fc.fault;
    Settings s = peerSettings(fc.effect, Mode::MrrEffect, 161, 97);
    s.effectMask.trim = false;  // the marks' faults on every level's whole stencil (§12.5's trim has its own)
    s.effectMask.cap = 4;
    s.effectMask.posterior = posteriorTau(fc.effect);
    // τ_v's marks, drawn by refinement_marks.frag where the faults are; the budget's (SPEC §12.4),
    // selected by refinement_budget.frag, with a share that leaves candidates out
    const bool budget = fc.fault.rfind("budget-", 0) == 0;
    s.effectMask.budget = budget ? 0.85f : 0.0f;
    if (budget) {
      s.effectMask.posterior = 0.01f;
      s.neverSlower = false;  // a frame this small would fall back
    }
    if (fc.fault == "refine-stencil-replaced") {
      s.levels[1].sigma2 = 0.0f;
      s.effectMask.firstLevel = 2;
    }
    const CostModel model = CostModel::defaults("cpu");
    const auto r = test::renderScene("builtin:" + fc.scene, s);
    Constants k = makeConstants(s, r.framedSize);
    if (fc.fault == "marks-inclusive") {
      const gpu::GpuRenderer clean(*r.scene);
      const FrameResult probe = clean.render(r.camera, k, {true, {}, &model});
      const std::map<float, int> counts = rangeCounts(probe.levels[static_cast<size_t>(k.coarsestEnabled)]);
      ASSERT_FALSE(counts.empty());
      const auto commonest = std::max_element(counts.begin(), counts.end(),
                                              [](const auto& a, const auto& b) { return a.second < b.second; });
      k.effectMask.posterior = commonest->first;
    }
    const FrameResult cpu = r.renderer->render(r.camera, k, {true, {}, &model});
    expectCaughtAt(r, k, model, cpu, *fault, fc.fault + ": ");
  }
}

// The planted fault trim-window-short (trim.frag's window along x s/2 short on the left) makes
// compareFrames fail first at the stencil; the same frame without it passes.
TEST(GpuTrimFaults, AShortWindowFailsAtTheStencil) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const gpu::ShaderFault* fault = nullptr;
  for (const gpu::ShaderFault& f : gpu::shaderFaults())
    if (f.name == "trim-window-short") fault = &f;
  ASSERT_NE(fault, nullptr);
  Settings s = peerSettings(Effect::Ssao, Mode::MrrEffect, 161, 97);
  s.effectMask.budget = 0.0f;
  s.effectMask.trim = true;
  const CostModel model = CostModel::defaults("cpu");
  const auto r = test::renderScene("builtin:demo", s);
  const Constants k = makeConstants(s, r.framedSize);
  const FrameResult cpu = r.renderer->render(r.camera, k, {true, {}, &model});
  expectCaughtAt(r, k, model, cpu, *fault, "trim-window-short: ");
}

// The planted fault effect-only-keeps-edges (STEP 4 without the ∧ ¬M_ℓ: each widened level is
// both's M'_ℓ again) makes compareFrames fail first at mask.L; the same frame without it passes.
TEST(GpuEffectOnlyFaults, KeepingTheEdgesFailsAtTheMask) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const gpu::ShaderFault* fault = nullptr;
  for (const gpu::ShaderFault& f : gpu::shaderFaults())
    if (f.name == "effect-only-keeps-edges") fault = &f;
  ASSERT_NE(fault, nullptr);
  const CostModel model = CostModel::defaults("cpu");
  const Settings s = effectOnlySettings(Effect::Ssao, false);
  const test::Rendered r = test::renderScene("builtin:demo", s);
  const Constants k = makeConstants(s, r.framedSize);
  const FrameResult cpu = r.renderer->render(r.camera, k, {true, {}, &model});
  expectCaughtAt(r, k, model, cpu, *fault, "");
}

// A sampling seed other than mrr's own (--seed) changes the kernels and the rotations on
// both paths alike: every stage still matches the oracle, and the effect differs from seed 0's.
TEST(GpuSeed, ANonDefaultSeedStillMatchesTheOracle) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const CostModel model = CostModel::defaults("cpu");
  for (Effect effect : {Effect::Ssao, Effect::Ssgi}) {
    Settings s = peerSettings(effect, Mode::Mrr, 97, 61);
    const BothPaths base = renderBoth("builtin:demo", s, model);
    s.seed = 12345;
    const BothPaths seeded = renderBoth("builtin:demo", s, model);
    const ParityResult r = compareFrames(seeded.cpu, seeded.port, seeded.oracle.scene->light);
    EXPECT_TRUE(r.pass()) << toString(effect) << ": first failing stage " << r.firstFailing() << "\n"
                          << formatParityTable(r);
    const StageRow* raw = r.row("raw.L2");  // every effect shades level 2 (Table 1)
    ASSERT_NE(raw, nullptr) << formatParityTable(r);
    ASSERT_TRUE(raw->sameInput);
    EXPECT_GT(raw->sameInput->figures.pixels, 0);
    // Not vacuous: the seed moved the effect on both paths.
    EXPECT_NE(seeded.cpu.levels[2].raw.data, base.cpu.levels[2].raw.data) << toString(effect);
    EXPECT_NE(seeded.port.levels[2].raw.data, base.port.levels[2].raw.data) << toString(effect);
  }
}

// --coarse-gbuffer render (docs/spec.md §1, the paper's convention): each coarse level rendered at
// its pixel centres, by rays on the oracle and rasterised at the level's size on the port; every
// stage still matches, and the levels are not the subsampled ones.
TEST(GpuCoarseGBuffer, RenderedLevelsMatchTheOracle) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const CostModel model = CostModel::defaults("cpu");
  for (const char* name : {"demo", "boxes"}) {
    const std::string scene = name;
    Settings s = peerSettings(Effect::Ssao, Mode::Mrr, 97, 61);
    const BothPaths subsampled = renderBoth("builtin:" + scene, s, model);
    s.renderCoarseGBuffer = true;
    const BothPaths rendered = renderBoth("builtin:" + scene, s, model);
    const ParityResult r = compareFrames(rendered.cpu, rendered.port, rendered.oracle.scene->light);
    EXPECT_TRUE(r.pass()) << scene << ": first failing stage " << r.firstFailing() << "\n" << formatParityTable(r);
    for (int l = 1; l < kLevelCount; ++l) {
      const size_t i = static_cast<size_t>(l);
      ASSERT_NE(r.row("gbuffer.L" + std::to_string(l) + ".depth"), nullptr) << l;
      EXPECT_NE(rendered.cpu.levels[i].gbuffer.depth.data, subsampled.cpu.levels[i].gbuffer.depth.data) << l;
      EXPECT_NE(rendered.port.levels[i].gbuffer.depth.data, subsampled.port.levels[i].gbuffer.depth.data) << l;
    }
    // Level 0 is the same in either mode.
    EXPECT_EQ(rendered.cpu.levels[0].gbuffer.depth.data, subsampled.cpu.levels[0].gbuffer.depth.data);
  }
}

}  // namespace
}  // namespace mrr
