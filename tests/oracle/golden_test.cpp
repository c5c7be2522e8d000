// Determinism regression: SHA-1 digests (OpenImageIO's computePixelHashSHA1) of the oracle's
// stages for every built-in scene and effect, against tests/golden/oracle.json. A change that
// moves any bit of any stage fails here, naming the stages that moved; a deliberate change is
// recorded again with
//
//   MRR_UPDATE_GOLDEN=1 build/tests/oracle_tests --gtest_filter='Golden.*'
//
// (scripts/update-golden.sh), and the new file is committed with the change that explains it.
// Embree's intersection kernels and glibc's libm pick code by CPU features, so digests are
// kept per instruction-set level; on a machine of a level with no record the test skips,
// saying how to record one.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/image_io.h"
#include "common/stages.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

using nlohmann::json;

const std::string kGoldenPath = std::string(MRR_SOURCE_DIR) + "/tests/golden/oracle.json";

std::string isaLevel() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return "x86-64-avx512";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "x86-64-avx2-fma";
  return "x86-64-baseline";
}

template <class Image>
std::string digest(const Image& image) {
  if (image.data.empty()) return "empty";
  using T = typename std::decay_t<decltype(image.data)>::value_type;
  const OIIO::TypeDesc type = sizeof(T) == 1 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
  const OIIO::ImageSpec spec(image.width, image.height, image.channels, type);
  const OIIO::ImageBuf buffer(spec, const_cast<T*>(image.data.data()));
  return OIIO::ImageBufAlgo::computePixelHashSHA1(buffer);
}

// The recorded stages, in pipeline order, named from the stage list (common/stages.h).
const std::vector<std::string> kStages = {partName(Part::GBuffer) + ".depth", partName(Part::GBuffer) + ".normal",
                                          partName(Part::ShadowMap), partName(Part::Edges), partName(Part::Alpha),
                                          partName(Part::Stencil), partName(Part::Sub), partName(Part::Final),
                                          partName(Part::Shaded)};

// One digest per stage; a stage spanning levels hashes the digests of its levels.
json stageDigests(const FrameResult& f) {
  auto levels = [&](auto&& pick) {
    std::string joined;
    for (int l = 0; l < kLevelCount; ++l)
      if (f.constants.levels[static_cast<size_t>(l)].enabled)
        joined += digest(pick(f.levels[static_cast<size_t>(l)])) + ";";
    return joined;
  };
  json j;
  j[kStages[0]] = levels([](const LevelResult& l) -> const ImageF& { return l.gbuffer.depth; });
  j[kStages[1]] = levels([](const LevelResult& l) -> const ImageF& { return l.gbuffer.normal; });
  j[kStages[2]] = digest(f.shadowMap.depth);
  j[kStages[3]] = digest(f.edges.combined);
  j[kStages[4]] = levels([](const LevelResult& l) -> const ImageF& { return l.masks.alpha; });
  j[kStages[5]] = levels([](const LevelResult& l) -> const ImageU8& { return l.masks.stencil; });
  j[kStages[6]] = levels([](const LevelResult& l) -> const ImageF& { return l.sub; });
  j[kStages[7]] = digest(f.final());
  j[kStages[8]] = digest(f.shaded);
  return j;
}

json renderAll() {
  json all;
  for (const std::string& scene : builtinSceneNames())
    for (const Effect effect : {Effect::Ssao, Effect::Ssm, Effect::Ssgi}) {
      Settings s = defaultSettings(effect);
      s.width = 96;
      s.height = 64;
      s.setSamples(effect == Effect::Ssao ? 8 : effect == Effect::Ssm ? 16 : 24);
      s.ssm.shadowMapSize = 256;
      s.neverSlower = false;  // the digests are of every stage of the method (SPEC §11 is tested apart)
      // The radii as recorded: the rule before the view-framed default (a fraction of the scene's diagonal), pinned,
      // so the digests keep the method's bits while the automatic radius follows the view.
      const float diagonal = makeBuiltinScene(scene).bounds().diagonal();
      s.ssao.radius = SsaoSettings::kDiagonalFractionBefore * diagonal;
      s.ssao.biasFraction = SsaoSettings::kBiasFractionBefore;
      s.ssgi.radius = SsgiSettings::kDiagonalFractionBefore * diagonal;
      const test::Rendered r = test::renderScene("builtin:" + scene, s);
      all[scene + "/" + toString(effect)] = stageDigests(r.frame);
    }
  return all;
}

TEST(Golden, OracleStagesMatchTheRecordedDigests) {
  const std::string isa = isaLevel();
  const json now = renderAll();
  json golden = json::object();
  if (std::filesystem::exists(kGoldenPath)) golden = json::parse(std::ifstream(kGoldenPath));
  if (const char* update = std::getenv("MRR_UPDATE_GOLDEN"); update && std::string(update) == "1") {
    golden["note"] = "SHA-1 of the oracle's stages at 96x64 (tests/oracle/golden_test.cpp); per CPU feature level";
    golden["levels"][isa] = now;
    std::filesystem::create_directories(std::filesystem::path(kGoldenPath).parent_path());
    writeTextFile(kGoldenPath, golden.dump(1) + "\n");
    GTEST_SKIP() << "recorded " << now.size() << " frames for " << isa << " in " << kGoldenPath;
  }
  if (!golden.contains("levels") || !golden["levels"].contains(isa))
    GTEST_SKIP() << "no digests recorded for " << isa << "; record them with MRR_UPDATE_GOLDEN=1 (scripts/update-golden.sh)";
  const json& recorded = golden["levels"][isa];
  EXPECT_EQ(recorded.size(), now.size()) << "the set of scenes or effects changed: record again";
  for (const auto& [frame, stages] : now.items()) {
    if (!recorded.contains(frame)) {
      ADD_FAILURE() << frame << ": no recorded digests";
      continue;
    }
    std::string moved;
    for (const std::string& stage : kStages)  // in pipeline order, so the first named is where it started
      if (recorded[frame].value(stage, "") != stages.value(stage, "")) moved += std::string(" ") + stage;
    EXPECT_TRUE(moved.empty()) << frame << ": stages that changed:" << moved
                               << " (the first is where to look; record again only if the change is intended)";
  }
}

}  // namespace
}  // namespace mrr
