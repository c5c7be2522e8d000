// The never-slower rule's counts (SPEC §11) on the GPU (gpu/rule.h, rule.frag summed by counts.frag)
// against the readable rule's on the host (common/frame.h countHits, countEdgeSample,
// countForRule) on the same frame's images read back: equal, count for count, so the port's
// decision is the host rule's on the port's own frame. Frames with the rule off but its counts
// taken (sampleWithRuleOff), so every count is made and nothing falls back; every effect, both
// methods the rule decides, odd sizes, a disabled level, a gaze.
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "common/cost_model.h"
#include "gpu/pipeline.h"
#include "scenes/catalog.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

struct CountsCase {
  std::string scene;
  Effect effect;
  Mode mode;
  int width, height;
  int disabledLevel = -1;
  bool gaze = false;
};

void PrintTo(const CountsCase& c, std::ostream* os) {
  *os << c.scene << " " << toString(c.effect) << " " << toString(c.mode) << " " << c.width << "x" << c.height
      << (c.disabledLevel >= 0 ? " without level " + std::to_string(c.disabledLevel) : "") << (c.gaze ? " gaze" : "");
}

class GpuRuleCounts : public ::testing::TestWithParam<CountsCase> {};

TEST_P(GpuRuleCounts, EqualTheHostRulesCountsOfTheSameImages) {
  MRR_REQUIRE_GL_OR_SKIP();
  const CountsCase& k = GetParam();
  SceneRequest req;
  req.scene = k.scene;
  const ResolvedScene rs = resolveScene(req);
  const gpu::GpuRenderer port(rs.scene);
  Settings s = defaultSettings(k.effect);
  s.width = k.width;
  s.height = k.height;
  s.setSamples(k.effect == Effect::Ssm ? 16 : 8);
  s.mode = k.mode;
  s.neverSlower = false;
  if (k.disabledLevel >= 0) s.levels[static_cast<size_t>(k.disabledLevel)].enabled = false;
  if (k.gaze) {
    s.foveation.gaze = true;
    s.foveation.gazeX = k.width / 3;
    s.foveation.gazeY = k.height / 2;
    s.foveation.ppd = 20.0f;
  }
  const Constants c = makeConstants(s, rs.framed.size);
  RenderOptions options{true, {}, nullptr};
  options.sampleWithRuleOff = true;
  const FrameResult f = port.render(rs.camera, c, options);
  ASSERT_TRUE(f.edgeSampled);
  if (k.effect == Effect::Ssm) ASSERT_FALSE(f.pcfSample.empty()) << "the PCF sample is counted too";
  // the host's readable rule on the images the frame read back
  const ImageU8& hit = f.levels[0].gbuffer.hit;
  FrameCounts host;
  ImageU8 silhouetteBlocks;
  countHits(host, hit, f.pcfSample, c, &silhouetteBlocks);
  countEdgeSample(host, f.edgeSample, silhouetteBlocks, hit, c);
  Masks masks;
  for (size_t l = 0; l < kLevelCount; ++l) masks[l] = f.levels[l].masks;
  countForRule(host, masks, c, hit, f.pcfSample);
  const FrameCounts& gpu = f.counts;
  EXPECT_GT(host.hitPixels, 0);
  EXPECT_EQ(gpu.hitPixels, host.hitPixels);
  EXPECT_EQ(gpu.searchedPixels, host.searchedPixels);
  EXPECT_EQ(gpu.pcfPixels, host.pcfPixels);
  EXPECT_EQ(gpu.searchedFootprint, host.searchedFootprint);
  EXPECT_EQ(gpu.edgeBlocks, host.edgeBlocks);
  EXPECT_GT(host.edgeBlocks, 0);
  for (size_t l = 0; l < kLevelCount; ++l) {
    EXPECT_EQ(gpu.silhouette[l], host.silhouette[l]) << "B_" << l;
    EXPECT_EQ(gpu.reach[l], host.reach[l]) << "R_" << l;
    EXPECT_EQ(gpu.reachHits[l], host.reachHits[l]) << "R_" << l << " on geometry";
    EXPECT_EQ(gpu.shaded[l], host.shaded[l]) << "|S_" << l << "|";
    EXPECT_EQ(gpu.shadedHit[l], host.shadedHit[l]) << "|S_" << l << " & hit|";
    EXPECT_EQ(gpu.shadedSearched[l], host.shadedSearched[l]) << "|S_" << l << " & searched|";
    EXPECT_EQ(gpu.shadedPcf[l], host.shadedPcf[l]) << "|S_" << l << " & pcf|";
  }
  if (k.effect == Effect::Ssm) EXPECT_GT(host.searchedFootprint, 0);
  // and so the same decision, to the bit
  const CostModel model = CostModel::defaults("gpu");
  EXPECT_EQ(decideFallback(model, c, gpu).predictedMrrMs, decideFallback(model, c, host).predictedMrrMs);
  EXPECT_EQ(decideEarly(model, c, gpu).predictedMrrMs, decideEarly(model, c, host).predictedMrrMs);
}

std::string countsCaseName(const ::testing::TestParamInfo<CountsCase>& info) {
  const CountsCase& c = info.param;
  std::string name = c.scene.substr(c.scene.find(':') + 1) + "_" + toString(c.effect) + "_" + toString(c.mode) + "_" +
                     std::to_string(c.width) + "x" + std::to_string(c.height);
  if (c.disabledLevel >= 0) name += "_noL" + std::to_string(c.disabledLevel);
  if (c.gaze) name += "_gaze";
  for (char& ch : name)
    if (ch == '-') ch = '_';
  return name;
}

std::vector<CountsCase> countsCases() {
  std::vector<CountsCase> out;
  for (Effect e : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
    out.push_back({"builtin:demo", e, Mode::Mrr, 161, 97});
    out.push_back({"builtin:demo", e, Mode::MrrEffect, 160, 90});
  }
  out.push_back({"builtin:shadows", Effect::Ssm, Mode::Mrr, 203, 117});
  out.push_back({"builtin:demo", Effect::Ssao, Mode::Mrr, 161, 97, 1});
  out.push_back({"builtin:demo", Effect::Ssao, Mode::Mrr, 161, 97, 3});
  out.push_back({"builtin:demo", Effect::Ssao, Mode::Mrr, 320, 180, -1, true});
  out.push_back({"arcade", Effect::Ssao, Mode::Mrr, 321, 181});
  return out;
}

INSTANTIATE_TEST_SUITE_P(Frames, GpuRuleCounts, ::testing::ValuesIn(countsCases()), countsCaseName);

}  // namespace
}  // namespace mrr
