// mrr-effect beyond the catalogue on the port: the separable range test gives the whole 3×3's bits
// and the oracle's (SPEC §12.2), the budget's marks are the oracle's selection on the port's own
// v (SPEC §12.4), and the temporal term is the oracle's on the port's own blend and history (§14).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <random>
#include <utility>

#include "common/cost_model.h"
#include "common/stages.h"
#include "common/tolerance.h"
#include "compare/parity/parity.h"
#include "cpu_ref/effect_masks.h"
#include "gpu/context.h"
#include "gpu/effect_masks.h"
#include "gpu/gbuffer.h"
#include "gpu/pipeline.h"
#include "scenes/cameras.h"
#include "tests/gpu/gl_test.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

using test::sameBits;


// refinement_marks.frag step 1: the separable passes (PASS 1, 2) and the whole 3×3 (PASS 0) give
// the same v, bit for bit, and the oracle's localRanges; the marks [v > τ] likewise.
TEST(GpuEffectBudget, SeparableRangeEqualsTheWholeNeighbourhoodAndTheOracle) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  Scene empty;
  const gpu::GpuScene scene(empty);
  std::mt19937 rng(11);
  for (const int channels : {1, 3}) {
    const int w = 61, h = 37;
    ImageF c(w, h, channels == 1 ? 1 : 4), positionHit(w, h, 4);
    ImageF oracleC(w, h, channels);
    ImageU8 stencil(w, h), hit(w, h);
    std::uniform_real_distribution<float> value(-0.3f, 1.2f);
    std::uniform_int_distribution<int> coin(0, 9);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        stencil.at(x, y) = coin(rng) > 1;
        hit.at(x, y) = coin(rng) > 0;
        positionHit.at(x, y, 3) = hit.at(x, y);
        for (int k = 0; k < channels; ++k) oracleC.at(x, y, k) = c.at(x, y, k) = value(rng);
      }
    gpu::TextureSet textures;
    const unsigned ct = textures.add(gpu::uploadTexture(c)), st = textures.add(gpu::uploadBinary(stencil)),
                   pt = textures.add(gpu::uploadTexture(positionHit));
    const gpu::Target separable = gpu::drawRangeTest(scene, ct, channels, st, pt, 0.2f, gpu::Cover::whole(), true, false);
    const gpu::Target whole = gpu::drawRangeTest(scene, ct, channels, st, pt, 0.2f, gpu::Cover::whole(), true, true);
    const ImageF a = separable->read(0, 1), b = whole->read(0, 1);
    EXPECT_TRUE(sameBits(a, b)) << channels << " channels";
    EXPECT_TRUE(sameBits(a, localRanges(oracleC, stencil, hit))) << channels << " channels: the oracle's v";
    const gpu::Target marks = gpu::drawRangeTest(scene, ct, channels, st, pt, 0.2f, gpu::Cover::whole(), false, false);
    EXPECT_EQ(marks->readBinary(0).data, variesAbove(localRanges(oracleC, stencil, hit), 0.2f).data);
  }
}

// A small mrr-effect frame: 97×61, 16 samples, without the never-slower rule (so that every frame
// refines).
Settings smallEffectFrame(Effect e) {
  Settings s = defaultSettings(e);
  s.width = 97;
  s.height = 61;
  s.setSamples(16);
  s.mode = Mode::MrrEffect;
  s.neverSlower = false;
  return s;
}

// smallEffectFrame at 161×97 with a budget whose share binds there (some candidates fit, some do
// not): the default B = 0.85 over the range test's marks at τ_v = 0.01, cap 4.
Settings bindingBudgetFrame(Effect e) {
  Settings s = smallEffectFrame(e);
  s.width = 161;
  s.height = 97;
  s.effectMask.cap = 4;
  s.effectMask.posterior = 0.01f;
  s.effectMask.budget = 0.85f;
  s.effectMask.trim = false;  // what §12.5's trim saves, the budget would spend: a share that binds
  return s;
}

struct BudgetFrames {
  test::Rendered oracle;
  FrameResult cpu, port;
};

// SPEC §12.4 on both paths: the port's marks are the oracle's selection on the port's own v and
// prices (exact), every stage within its rule, and each level spends no more than its share.
TEST(GpuEffectBudget, BudgetedMarksAreTheOraclesSelection) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const CostModel model = CostModel::defaults("cpu");
  for (const Effect e : {Effect::Ssao, Effect::Ssgi}) {
    const Settings s = bindingBudgetFrame(e);
    BudgetFrames b;
    b.oracle = test::renderScene("builtin:demo", s);
    const Constants k = makeConstants(s, b.oracle.framedSize);
    b.cpu = b.oracle.renderer->render(b.oracle.camera, k, {true, {}, &model, true});
    const gpu::GpuRenderer port(*b.oracle.scene);
    b.port = port.render(b.oracle.camera, k, {true, {}, &model, true});
    const ParityResult r = compareFrames(b.cpu, b.port, b.oracle.scene->light);
    EXPECT_TRUE(r.pass()) << toString(e) << ": first failing stage " << r.firstFailing() << "\n" << formatParityTable(r);
    int64_t taken = 0;
    int bound = 0;  // levels that spent some of their share and left candidates out: the search was tested
    for (int l = 0; l < kLevelCount; ++l) {
      const RefinementRecord& rec = b.port.refinement[static_cast<size_t>(l)];
      if (!rec.budgeted) continue;
      EXPECT_LE(rec.spentUnits, rec.shareUnits);
      bound += rec.spentUnits > 0 && rec.taken < rec.candidates ? 1 : 0;
      taken += rec.taken;
      const StageRow* marks = r.row("marks.L" + std::to_string(l));
      ASSERT_NE(marks, nullptr) << formatParityTable(r);
      ASSERT_TRUE(marks->sameInput);
      EXPECT_EQ(marks->sameInput->figures.maxAbs, 0.0) << "marks.L" << l;
    }
    EXPECT_GT(taken, 0) << toString(e) << ": the budget took nothing, the check would be vacuous";
    EXPECT_GT(bound, 0) << toString(e) << ": every candidate fitted, the threshold was not searched";
  }
}

// Three frames along an orbit on both paths, each path carrying its own history (SPEC §14): the
// third frame of each, with the stages.
std::pair<FrameResult, FrameResult> thirdFrameOfAnOrbit(const test::Rendered& base, const Constants& k,
                                                        const CostModel& model) {
  const gpu::GpuRenderer port(*base.scene);
  const std::vector<Camera> path = cameraPath(base.camera, "orbit", 12);
  FrameHistory cpuHistory, portHistory;
  FrameResult cpu, gpuFrame;
  for (int t = 0; t < 3; ++t) {
    RenderOptions co{true, {}, &model}, po{true, {}, &model};
    if (!cpuHistory.empty()) co.history = &cpuHistory;
    if (!portHistory.empty()) po.history = &portHistory;
    cpu = base.renderer->render(path[static_cast<size_t>(t)], k, co);
    gpuFrame = port.render(path[static_cast<size_t>(t)], k, po);
    cpuHistory = cpu.history;
    portHistory = gpuFrame.history;
  }
  return {std::move(cpu), std::move(gpuFrame)};
}

// SPEC §14.2 on both paths along an orbit: the budget's second and third frames read each path's
// previous selection (uploaded to the port's keys pass), and the port's marks are the oracle's
// selection on the port's own v, prices and previous selection, exact; some candidates kept their
// mark by the hysteresis, so the check is not vacuous.
TEST(GpuEffectBudget, TheMarksHysteresisIsTheOraclesOnThePortsOwnHistory) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const CostModel model = CostModel::defaults("cpu");
  for (const Effect e : {Effect::Ssao, Effect::Ssm}) {
    Settings s = bindingBudgetFrame(e);
    s.effectMask.temporal = 0.5f;  // a previous frame, and so a previous selection
    s.effectMask.hysteresis = 0.5f;
    test::Rendered base = test::renderScene("builtin:demo", s);
    const Constants k = makeConstants(s, base.framedSize);
    const auto [cpu, gpuFrame] = thirdFrameOfAnOrbit(base, k, model);
    const ParityResult r = compareFrames(cpu, gpuFrame, base.scene->light);
    int64_t kept = 0;
    for (int l = 0; l < kLevelCount; ++l) {
      const RefinementRecord& rec = gpuFrame.refinement[static_cast<size_t>(l)];
      if (!rec.budgeted) continue;
      ASSERT_FALSE(rec.previousMarked.empty()) << "level " << l << ": no previous selection";
      kept += rec.kept;
      const StageRow* marks = r.row("marks.L" + std::to_string(l));
      ASSERT_NE(marks, nullptr) << formatParityTable(r);
      ASSERT_TRUE(marks->sameInput);
      EXPECT_EQ(marks->sameInput->figures.maxAbs, 0.0) << toString(e) << " marks.L" << l << "\n" << formatParityTable(r);
    }
    EXPECT_GT(kept, 0) << toString(e) << ": no candidate kept its mark, the check would be vacuous";
  }
}

// SPEC §14 on both paths along an orbit: each path carries its own history; on the third frame the
// port's temporal term is the oracle's on the port's own blend, G-buffer, masks and history.
TEST(GpuTemporal, TheTermIsTheOraclesOnThePortsOwnHistory) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const CostModel model = CostModel::defaults("cpu");
  for (const Effect e : {Effect::Ssao, Effect::Ssgi}) {
    Settings s = smallEffectFrame(e);
    s.effectMask.temporal = 0.6f;
    test::Rendered base = test::renderScene("builtin:demo", s);
    const Constants k = makeConstants(s, base.framedSize);
    const auto [cpu, gpuFrame] = thirdFrameOfAnOrbit(base, k, model);
    ASSERT_FALSE(gpuFrame.temporal.empty());
    const ParityResult r = compareFrames(cpu, gpuFrame, base.scene->light);
    EXPECT_TRUE(r.pass()) << toString(e) << ": first failing stage " << r.firstFailing() << "\n" << formatParityTable(r);
    const StageRow* row = r.row(partName(Part::Temporal));
    ASSERT_NE(row, nullptr) << formatParityTable(r);
    ASSERT_TRUE(row->sameInput);
    EXPECT_TRUE(row->sameInput->pass);
    int64_t kept = 0;
    for (float w : gpuFrame.temporal.weight.data) kept += w > 0.0f;
    EXPECT_GT(kept, 0) << "no pixel kept its history: the check would be vacuous";
  }
}

// The planted fault temporal-keeps-level-zero (λ_p = λ, the (1 − α_0) dropped): the port's second
// frame of a still camera fails first at the temporal part; without the fault it passes.
TEST(GpuTemporal, APlantedFaultFailsAtTheTemporalPart) {
  MRR_REQUIRE_GL_OR_SKIP();
  const gpu::GlContext context;
  const CostModel model = CostModel::defaults("cpu");
  Settings s = smallEffectFrame(Effect::Ssao);
  s.effectMask.temporal = 0.6f;
  test::Rendered base = test::renderScene("builtin:demo", s);
  const Constants k = makeConstants(s, base.framedSize);
  const auto second = [&](const FrameRenderer& r) {
    const FrameResult first = r.render(base.camera, k, {false, {}, &model});
    RenderOptions o{true, {}, &model};
    o.history = &first.history;
    return r.render(base.camera, k, o);
  };
  const FrameResult cpu = second(*base.renderer);
  {
    const gpu::GpuRenderer clean(*base.scene);
    const ParityResult ok = compareFrames(cpu, second(clean), base.scene->light);
    EXPECT_TRUE(ok.pass()) << "without the fault\n" << formatParityTable(ok);
  }
  setenv("MRR_GPU_FAULT", "temporal-keeps-level-zero", 1);
  const gpu::GpuRenderer faulty(*base.scene);
  const ParityResult bad = compareFrames(cpu, second(faulty), base.scene->light);
  unsetenv("MRR_GPU_FAULT");
  EXPECT_FALSE(bad.pass()) << formatParityTable(bad);
  EXPECT_EQ(bad.firstFailing().rfind(partName(Part::Temporal), 0), 0u)
      << "first failing stage " << bad.firstFailing() << ", expected temporal\n" << formatParityTable(bad);
}

}  // namespace
}  // namespace mrr
