// The bench's foveation group (compare/bench/bench_fovea.h, SPEC §13) on the oracle: the rings count what
// SPEC §13 promises (the fovea keeps the method's decisions, the periphery shades fewer), the
// motion runs shade fewer pixels where the camera moves, and the figures reach JSON, CSV and
// Markdown.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "compare/bench/bench.h"
#include "tests/oracle/bench_helpers.h"
#include "compare/bench/bench_fovea.h"
#include "compare/bench/bench_report.h"
#include "render_helpers.h"
#include "tests/test_support.h"

namespace mrr {
namespace {

TEST(BenchFovea, RingsFollowTheEccentricityInDegrees) {
  EXPECT_EQ(foveaRing(0, 0, 30.0), 0);
  EXPECT_EQ(foveaRing(59, 0, 30.0), 0);    // 1.97°
  EXPECT_EQ(foveaRing(60, 0, 30.0), 1);    // 2°
  EXPECT_EQ(foveaRing(0, -150, 30.0), 2);  // 5°
  EXPECT_EQ(foveaRing(180, 240, 30.0), 3); // 300 px: 10°
  EXPECT_EQ(foveaRing(900, 0, 30.0), 5);   // 30°: the open ring
  EXPECT_EQ(foveaRing(5000, 5000, 30.0), 5);
}

TEST(BenchFovea, TheFoveaKeepsTheMethodsDecisionsThePeripheryAndMotionShadeLess) {
  const std::string dir = test::scratchDir();
  BenchOptions o;
  o.foveaOnly = true;
  o.foveaScenes = {"builtin:demo"};
  o.foveaMethods = {"mrr-norule", "tiles"};  // mrr without the never-slower rule: its masks, whatever the cost
  o.foveaSize = {640, 360};
  o.foveaMotionSize = {320, 180};
  // ppd 30: level 1 from 153.4 px (5.11°), level 2 from 335.2 px (11.2°). The ring 0–2° (60 px)
  // lies inside the fovea, far beyond the blur's reach; the rings from 5° out lie outside it.
  o.foveaPpds = {30.0};
  o.foveaSamples = 8;
  o.foveaFrames = 5;  // orbit 0°, 12°, 0°, −12°, 0°; dolly 0, 0.15, 0.3, 0.15, 0
  o.repeats = 1;
  o.jsonOut = dir + "/bench.json";
  o.csvOut = dir + "/bench.csv";
  o.markdownOut = dir + "/bench.md";
  const BenchPath cpu = oracleBenchPath();
  std::ostringstream out;
  ASSERT_EQ(runBench(o, {cpu}, out), 0);
  const nlohmann::json j = nlohmann::json::parse(test::readFile(o.jsonOut));
  EXPECT_TRUE(j.at("runs").empty()) << "--fovea-only runs no other group";
  EXPECT_TRUE(j.at("sanity_failures").empty()) << j.at("sanity_failures").dump();

  // Rings: by method, ring → record.
  std::map<std::string, std::vector<nlohmann::json>> rings;
  for (const nlohmann::json& r : j.at("fovea").at("rings")) rings[r.at("method").get<std::string>()].push_back(r);
  for (const char* m : {"full", "mrr-norule", "mrr-norule+gaze", "tiles", "tiles+gaze"}) ASSERT_EQ(rings[m].size(), 4u) << m << ": 0–2, 2–5, 5–10, 10–20°";
  for (const nlohmann::json& r : rings["full"]) {
    EXPECT_EQ(r.at("shaded_share").get<double>(), 1.0);
    EXPECT_EQ(r.at("rms").get<double>(), 0.0);
  }
  for (const std::string base : {"mrr-norule", "tiles"}) {
    long long total = 0;
    for (size_t i = 0; i < 4; ++i) {
      const nlohmann::json& own = rings[base][i];
      const nlohmann::json& fov = rings[base + "+gaze"][i];
      const long long a = own.at("shaded_level_pixels").get<long long>(), b = fov.at("shaded_level_pixels").get<long long>();
      total += b;
      EXPECT_LE(b, a) << base << " ring " << i << ": the limit only clears masks";
      if (base == "mrr-norule" && i == 0) {  // inside the fovea: mrr's decisions and mrr's image
        EXPECT_EQ(b, a) << "ring " << i;
        EXPECT_EQ(fov.at("rms").get<double>(), own.at("rms").get<double>()) << "ring " << i;
      }
      if (i >= 2) {  // 5–10° and 10–20°: level 0 (and from 11.2° level 1) gone; measured 0.49–0.59x
        EXPECT_LT(fov.at("shaded_share").get<double>(), 0.75 * own.at("shaded_share").get<double>()) << base << " ring " << i;
        EXPECT_GT(fov.at("rms").get<double>(), own.at("rms").get<double>()) << base << " ring " << i << ": coarser costs error";
      }
    }
    // The rings partition the frame's shaded level pixels.
    EXPECT_NEAR(static_cast<double>(total), rings[base + "+gaze"][0].at("frame_share").get<double>() * 640 * 360, 0.5) << base;
  }

  // Motion: every frame after the first of both paths, each method with and without the previous frame.
  const nlohmann::json& motion = j.at("fovea").at("motion");
  ASSERT_EQ(motion.size(), 2u * 4u * 4u) << "2 paths x 4 frames x (mrr-norule, +motion, tiles, +motion)";
  std::map<std::string, double> still;
  for (const nlohmann::json& r : motion)
    if (r.at("method").get<std::string>().find("+motion") == std::string::npos)
      still[r.at("camera_path").get<std::string>() + std::to_string(r.at("frame").get<int>()) + r.at("method").get<std::string>()] =
          r.at("shaded_share").get<double>();
  int fast = 0;
  for (const nlohmann::json& r : motion) {
    const std::string m = r.at("method").get<std::string>();
    const size_t plus = m.find("+motion");
    if (plus == std::string::npos) continue;
    const double own = still.at(r.at("camera_path").get<std::string>() + std::to_string(r.at("frame").get<int>()) + m.substr(0, plus));
    EXPECT_LE(r.at("shaded_share").get<double>(), own) << r.dump();
    if (r.at("mean_speed").get<double>() >= 8.0) {  // most pixels may take level 2
      EXPECT_LT(r.at("shaded_share").get<double>(), 0.8 * own) << r.dump();
      ++fast;
    }
  }
  EXPECT_GT(fast, 0) << "the orbit's 12° steps move the demo by more than 8 px";

  // The files.
  const std::string ringsCsv = test::readFile(dir + "/bench-fovea.csv");
  EXPECT_EQ(std::count(ringsCsv.begin(), ringsCsv.end(), '\n'), 1 + static_cast<long>(j.at("fovea").at("rings").size()));
  const std::string motionCsv = test::readFile(dir + "/bench-fovea-motion.csv");
  EXPECT_EQ(std::count(motionCsv.begin(), motionCsv.end(), '\n'), 1 + static_cast<long>(motion.size()));
  const std::string md = test::readFile(o.markdownOut);
  EXPECT_NE(md.find("### Foveation: per eccentricity ring"), std::string::npos);
  EXPECT_NE(md.find("### Motion: shaded share against screen speed"), std::string::npos);
}

TEST(BenchFovea, ASanityCheckCatchesAGazeThatShadesMore) {
  FoveaResults res;
  FoveaRingRecord own;
  own.path = "cpu";
  own.scene = "s";
  own.method = "mrr";
  own.ppd = 30.0;
  own.pixels = 100;
  own.shadedLevelPixels = 40;
  own.shadedShare = 0.4;
  FoveaRingRecord fov = own;
  fov.method = "mrr+gaze";
  res.rings = {own, fov};
  EXPECT_TRUE(foveaSanityChecks(res).empty());
  res.rings[1].shadedLevelPixels = 41;  // planted: the gaze shading more than the method alone
  ASSERT_EQ(foveaSanityChecks(res).size(), 1u);
  EXPECT_NE(foveaSanityChecks(res)[0].find("more than without the gaze"), std::string::npos);
  res.rings[1].fellBack = true;  // a frame the rule shaded at full res is not held to it
  EXPECT_TRUE(foveaSanityChecks(res).empty());
  res.rings[1].fellBack = false;
  res.rings[1].budgeted = true;  // nor one whose budget spent the time the gaze freed (SPEC §12.4)
  EXPECT_TRUE(foveaSanityChecks(res).empty());
}

}  // namespace
}  // namespace mrr
