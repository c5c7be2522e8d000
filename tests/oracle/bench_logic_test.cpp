// The benchmark's own logic: the flicker figure (SPEC §10), the sanity checks that CI runs on
// `mrr bench --quick`, and reading the paper's figures. Each check is shown to fire.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/stages.h"
#include "compare/bench/bench.h"
#include "tests/oracle/bench_helpers.h"
#include "compare/bench/bench_report.h"
#include "compare/metrics/flip.h"
#include "compare/metrics/metrics.h"
#include "compare/rule/rule.h"
#include "render_helpers.h"
#include "scenes/cameras.h"
#include "tests/test_support.h"

namespace mrr {
namespace {

ImageF filled(float v) { return ImageF(8, 4, 1, v); }

TEST(Flicker, SteadyErrorIsZeroWhateverTheSceneDoes) {
  FlickerMeter m;
  for (int t = 0; t < 5; ++t) m.add(filled(0.1f * t + 0.05f), filled(0.1f * t));  // error 0.05 every frame
  EXPECT_NEAR(m.flicker(), 0.0, 1e-7);
  EXPECT_NEAR(m.meanRms(), 0.05, 1e-6);
  EXPECT_EQ(m.frames(), 5);
}

TEST(Flicker, AnErrorThatFlipsSignEachFrameFlickersByTwiceItsSize) {
  FlickerMeter m;
  for (int t = 0; t < 4; ++t) m.add(filled(t % 2 ? 0.47f : 0.53f), filled(0.5f));
  EXPECT_NEAR(m.flicker(), 0.06, 1e-6);
}

// Without FLIP (the bench's meters against the expectation) the flicker and the mean RMS are
// the same figures, and the FLIP ones are 0.
TEST(Flicker, WithoutFlipTheFlickerAndRmsAreTheSame) {
  FlickerMeter with, without(false);
  for (int t = 0; t < 4; ++t) {
    const ImageF frame = filled(t % 2 ? 0.47f : 0.53f), ref = filled(0.5f + 0.01f * static_cast<float>(t));
    with.add(frame, ref);
    without.add(frame, ref);
  }
  EXPECT_GT(with.flicker(), 0.0);
  EXPECT_EQ(without.flicker(), with.flicker());
  EXPECT_EQ(without.meanRms(), with.meanRms());
  EXPECT_EQ(without.frames(), 4);
  EXPECT_GT(with.meanFlip(), 0.0);
  EXPECT_EQ(without.flipFlicker(), 0.0);
  EXPECT_EQ(without.meanFlip(), 0.0);
}

// A grey ramp with a bright square planted in the middle, or without it.
ImageF scene(bool planted) {
  ImageF img(48, 32, 1, 0.0f);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const bool inSquare = x >= 18 && x < 30 && y >= 10 && y < 22;
      img.at(x, y) = 0.2f + 0.01f * static_cast<float>(x) + (planted && inSquare ? 0.35f : 0.0f);
    }
  return img;
}

TEST(Flicker, FlipFlickerIsZeroForASteadyErrorAndTheWholeFlipOfOneThatComesAndGoes) {
  const double planted = flip(scene(false), scene(true)).stats.mean;
  ASSERT_GT(planted, 0.01) << "the planted square is visible";
  FlickerMeter steady, blinking;
  for (int t = 0; t < 4; ++t) {
    steady.add(scene(true), scene(false));
    blinking.add(scene(t % 2 == 1), scene(false));  // no error, the square, none, the square
  }
  EXPECT_EQ(steady.flipFlicker(), 0.0);
  EXPECT_NEAR(steady.meanFlip(), planted, 1e-9);
  // Every step changes the FLIP map from 0 to the square's map or back: |ΔFLIP| = its FLIP.
  EXPECT_NEAR(blinking.flipFlicker(), planted, 1e-7);
  EXPECT_NEAR(blinking.meanFlip(), planted / 2.0, 1e-9);
  EXPECT_GT(blinking.flicker(), 0.0);
  FlickerMeter one;
  one.add(scene(true), scene(false));
  EXPECT_EQ(one.flipFlicker(), 0.0) << "no frame-to-frame change before two frames";
}

TEST(Flicker, RejectsFramesOfDifferentSizes) {
  FlickerMeter m;
  m.add(filled(0.0f), filled(0.0f));
  EXPECT_THROW(m.add(ImageF(4, 4), ImageF(4, 4)), MrrError);
}

BenchRecord record(const std::string& method, double ideal, double measured, double rms) {
  BenchRecord r;
  r.path = "cpu";
  r.scene = "builtin:demo";
  r.group = "main";
  r.method = method;
  r.effect = "ssao";
  r.width = 64;
  r.height = 32;
  r.samples = 16;
  r.shadedPixels = static_cast<long long>(64 * 32 / ideal);
  r.idealSpeedup = ideal;
  r.measuredSpeedup = measured;
  r.fullEffectMs = 50.0;
  r.error.rms = rms;
  r.error.maxAbs = rms * 4;
  return r;
}

TEST(BenchSanity, PassesHonestFiguresAndCatchesEachPlantedFault) {
  BenchResults ok;
  ok.records = {record("full", 1.0, 1.0, 0.0), record("mrr", 2.5, 1.8, 0.004), record("uniform-2", 16.0, 5.0, 0.03)};
  EXPECT_TRUE(sanityChecks(ok).empty());

  BenchResults fullErr = ok;  // full differs from its own repeat: not deterministic
  fullErr.records[0].error.rms = 1e-6;
  EXPECT_EQ(sanityChecks(fullErr).size(), 1u);

  BenchResults tooFast = ok;  // faster than its shaded-pixel ratio allows
  tooFast.records[1].measuredSpeedup = 4.0;
  ASSERT_EQ(sanityChecks(tooFast).size(), 1u);
  EXPECT_NE(sanityChecks(tooFast)[0].find("above the ideal"), std::string::npos);

  BenchResults jitter = ok;  // a fallen-back frame a few ms faster than full: timing jitter
  jitter.records[1].idealSpeedup = 1.0;
  jitter.records[1].fullEffectMs = 13.5;
  jitter.records[1].measuredSpeedup = 1.35;
  EXPECT_TRUE(sanityChecks(jitter).empty());
  jitter.records[1].measuredSpeedup = 3.0;  // ... but not many ms faster
  EXPECT_EQ(sanityChecks(jitter).size(), 1u);

  BenchResults tooShort = tooFast;  // ... unless full's time is too short to mean anything
  tooShort.records[1].fullEffectMs = 2.0;
  EXPECT_TRUE(sanityChecks(tooShort).empty());

  BenchResults moreThanFull = ok;  // ... or the method shades more pixels than full (alledges)
  moreThanFull.records[1].idealSpeedup = 0.72;
  moreThanFull.records[1].measuredSpeedup = 0.96;
  EXPECT_TRUE(sanityChecks(moreThanFull).empty());

  BenchResults fellBack = ok;  // a fallen-back frame must be the full frame
  fellBack.records[1].fellBack = true;
  EXPECT_EQ(sanityChecks(fellBack).size(), 1u);
  // ... and when it is, its time against full's is noise: no above-the-ideal check (CI: 1.40×)
  BenchResults fellBackFast = tooFast;
  fellBackFast.records[1].fellBack = true;
  fellBackFast.records[1].idealSpeedup = 1.0;
  fellBackFast.records[1].error = {};
  EXPECT_TRUE(sanityChecks(fellBackFast).empty());

  BenchResults fullPixels = ok;  // full shades W·H
  fullPixels.records[0].shadedPixels = 100;
  EXPECT_EQ(sanityChecks(fullPixels).size(), 1u);
}

// mrr-effect's bench variants (SPEC §12): +e is the effect-only arm, +norule turns the rule off
// (as mrr-norule), and they combine in either order; mrr-effect alone keeps the rule.
TEST(BenchMethods, EffectOnlyAndNoRuleVariantsSetTheirSettings) {
  const Settings plain = settingsFor("mrr-effect", Effect::Ssm, 64, 48, 16);
  EXPECT_TRUE(plain.neverSlower);
  EXPECT_FALSE(plain.effectMask.effectOnly);
  for (const char* m : {"mrr-effect+e+norule", "mrr-effect+norule+e"}) {
    const Settings s = settingsFor(m, Effect::Ssm, 64, 48, 16);
    EXPECT_EQ(s.mode, Mode::MrrEffect) << m;
    EXPECT_FALSE(s.neverSlower) << m;
    EXPECT_TRUE(s.effectMask.effectOnly) << m;
  }
  const Settings rule = settingsFor("mrr-effect+e", Effect::Ssm, 64, 48, 16);
  EXPECT_TRUE(rule.neverSlower);
  EXPECT_FALSE(settingsFor("mrr-effect+norule", Effect::Ssm, 64, 48, 16).neverSlower);
  EXPECT_FALSE(settingsFor("mrr-norule", Effect::Ssm, 64, 48, 16).neverSlower);  // the old spelling of mrr+norule
  EXPECT_FALSE(settingsFor("mrr+norule", Effect::Ssm, 64, 48, 16).neverSlower);
  // A switch is its method's row's: mrr has no widening, tiles no rule.
  EXPECT_THROW(settingsFor("mrr+c4", Effect::Ssm, 64, 48, 16), MrrError);
  EXPECT_THROW(settingsFor("tiles+norule", Effect::Ssm, 64, 48, 16), MrrError);
  // Each switch sets its frame parameter as the command line would, and is checked as it is.
  EXPECT_EQ(settingsFor("mrr-effect+c4+p0.15", Effect::Ssao, 64, 48, 16).effectMask.cap, 4);
  EXPECT_EQ(settingsFor("mrr-effect+c4+p0.15", Effect::Ssao, 64, 48, 16).effectMask.posterior, 0.15f);
  EXPECT_THROW(settingsFor("mrr-effect+c99", Effect::Ssao, 64, 48, 16), MrrError);  // --effect-cap's range
}

TEST(PaperFiguresCsv, ReadsSpeedupsAsFactorsAndRms) {
  const std::string path = (std::filesystem::temp_directory_path() / "mrr-paper-figures.csv").string();
  {
    std::ofstream f(path);
    f << "# comment\nfigure,effect,samples,width,height,speedup_pct,rms\n"
      << "fig7,ssm,196,1280,720,-17.4,\nfig9,ssao,64,1920,1080,,0.00731286\n";
  }
  const auto p = readPaperFigures(path);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_NEAR(p[0].speedup, 0.826, 1e-9);
  EXPECT_EQ(p[0].height, 720);
  EXPECT_DOUBLE_EQ(p[1].rms, 0.00731286);
  EXPECT_TRUE(readPaperFigures("/nonexistent/paper.csv").empty());
  std::filesystem::remove(path);
}

TEST(BenchCameras, TheFirstIsTheSceneCameraAndTheOthersDiffer) {
  const Camera base = lookAt({4, 3, 6}, {0, 1, -1}, 60.0f);
  const auto cams = benchCameras(base, 8);
  ASSERT_EQ(cams.size(), 8u);
  EXPECT_EQ(cams[0].eye, base.eye);
  EXPECT_EQ(cams[0].target, base.target);
  for (size_t i = 1; i < cams.size(); ++i) {
    const glm::vec3 d0 = glm::normalize(cams[0].target - cams[0].eye), di = glm::normalize(cams[i].target - cams[i].eye);
    EXPECT_TRUE(glm::dot(d0, di) < 0.99999f || glm::length(cams[i].eye - base.eye) > 1e-3f) << "camera " << i;
  }
}

TEST(CameraPaths, StartAndEndAtTheSceneCameraAndMoveSmoothly) {
  const Camera base = lookAt({4, 3, 6}, {0, 1, -1}, 60.0f);
  for (const std::string& kind : cameraPathKinds()) {
    const auto path = cameraPath(base, kind, 60);
    ASSERT_EQ(path.size(), 60u);
    EXPECT_LT(glm::length(path.front().eye - base.eye), 1e-5f) << kind;
    EXPECT_LT(glm::length(path.back().eye - base.eye), 1e-5f) << kind;
    float largest = 0.0f, total = 0.0f;
    for (size_t t = 1; t < path.size(); ++t) {
      const float step = glm::length(path[t].eye - path[t - 1].eye);
      largest = std::max(largest, step);
      total += step;
    }
    EXPECT_GT(total, 0.5f) << kind << " moves";
    EXPECT_LT(largest, 4.0f * total / 59.0f) << kind << " has no jump";
  }
  EXPECT_THROW(cameraPath(base, "spin", 60), MrrError);
}

// Every timing name a real oracle frame records is a row of the stage list (common/stages.h
// kTimed), of the oracle's or both paths': every effect, every mode, the rule on (kept, and
// fallen back early with a model that prices the method dear) and off. The rule sweep's sums
// then hold every stage, and their classes add up to the stages' sum.
TEST(TimedStages, EveryNameAnOracleFrameRecordsIsInTheStageList) {
  CostModel dear = CostModel::defaults("cpu");
  for (EffectCost& ec : dear.effect) ec.fixedMs = 1e6;  // the method can never pay: it falls back early
  SceneRequest req;
  req.scene = "builtin:shadows";
  const ResolvedScene rs = resolveScene(req);
  const Renderer renderer(rs.scene);
  std::set<std::string> seen;
  for (Effect effect : {Effect::Ssao, Effect::Ssm, Effect::Ssgi})
    for (const MethodInfo& row : methods())  // every row of the method table; the rule's three ways where it applies
      for (int variant = 0; variant < (row.neverSlower ? 3 : 1); ++variant) {
        const Mode mode = row.mode;
        Settings s = defaultSettings(effect);
        s.width = 48;
        s.height = 32;
        s.mode = mode;
        s.setSamples(effect == Effect::Ssm ? 16 : 4);
        s.ssm.shadowMapSize = 128;
        s.neverSlower = variant > 0;
        if (mode == Mode::MrrEffect) s.effectMask.temporal = 0.5f;  // the temporal stage runs (and keeps its history)
        RenderOptions options{false, {}, variant == 2 ? &dear : nullptr, true};
        const FrameResult f = renderer.render(rs.camera, makeConstants(s, rs.framed.size), options);
        const std::string what = toString(effect) + " " + toString(mode) + " variant " + std::to_string(variant);
        if (variant == 2) EXPECT_TRUE(f.fallback.fellBack) << what;
        double sum = 0.0;
        for (const StageTiming& t : f.timings) {
          const std::optional<TimedStage> stage = findTimed(t.stage);
          ASSERT_TRUE(stage.has_value()) << what << ": " << t.stage << " is not in common/stages.h's kTimed";
          EXPECT_NE(stage->info().on, TimedOn::Port) << what << ": " << t.stage;
          if (stage->timed != Timed::Total) sum += t.ms;
          seen.insert(std::string(stage->info().name));
        }
        ASSERT_FALSE(f.timings.empty());
        EXPECT_EQ(f.timings.back().stage, timedName(Timed::Total)) << what;
        const std::map<std::string, double> ms = stageMs(f);
        double classes = 0.0;
        for (CostClass c : {CostClass::Shared, CostClass::Detection, CostClass::Viewing, CostClass::Shading,
                            CostClass::LevelPixel, CostClass::Rest})
          classes += costClassMs(ms, c);
        EXPECT_NEAR(classes, sum, 1e-9 * std::max(sum, 1.0)) << what;
        EXPECT_EQ(costClassMs(ms, CostClass::Total), f.timing(timedName(Timed::Total))) << what;
      }
  // and the oracle's frames time every stage of the list but the port's own
  for (const TimedInfo& t : kTimed)
    EXPECT_EQ(seen.count(std::string(t.name)), t.on == TimedOn::Port ? 0u : 1u) << t.name;
}

// The rule sweep counts its frames per path as scenes × kRuleViewCount × configurations per view.
TEST(RuleViews, AreTheCountTheSweepPlansFor) {
  SceneRequest req;
  req.scene = "builtin:demo";
  const ResolvedScene rs = resolveScene(req);
  const std::vector<RuleView> views = ruleViews(rs.scene, rs.camera, 16.0f / 9.0f);
  ASSERT_EQ(views.size(), kRuleViewCount);
  std::set<std::string> names;
  for (const RuleView& v : views) names.insert(v.name);
  EXPECT_EQ(names, (std::set<std::string>{"catalogue", "default", "sky", "close-up"}));
}

// The bench end to end on tiny frames: its stability table carries FLIP beside RMS in the
// JSON, the stability CSV and the Markdown, and a method at a quarter of the pixels along a
// moving camera has a FLIP error that changes from frame to frame.
TEST(BenchStability, TheFlickerTableCarriesFlipInJsonCsvAndMarkdown) {
  const std::string dir = test::scratchDir();
  BenchOptions o;
  o.scenes = {"builtin:demo"};
  o.sizes = {{32, 18}};
  o.effects = {"ssao"};
  o.samples = {4};
  o.methods = {"full", "uniform-2", "mrr"};
  o.cameras = 1;
  o.repeats = 1;
  o.paperSweeps = false;
  o.frames = 4;
  o.stabilitySize = {64, 36};
  o.stabilityScenes = {"builtin:demo"};
  o.stressScenes = {};
  o.jsonOut = dir + "/bench.json";
  o.csvOut = dir + "/bench.csv";
  o.markdownOut = dir + "/bench.md";
  const BenchPath cpu = oracleBenchPath();
  std::ostringstream out;
  ASSERT_EQ(runBench(o, {cpu}, out), 0);

  const nlohmann::json j = nlohmann::json::parse(test::readFile(o.jsonOut));
  ASSERT_EQ(j.at("stability").size(), 2u * cameraPathKinds().size()) << "uniform-2 and mrr on every camera path";
  for (const nlohmann::json& s : j.at("stability")) {
    const double flipFlicker = s.at("flip_flicker").get<double>(), meanFlip = s.at("mean_flip").get<double>();
    EXPECT_GE(flipFlicker, 0.0);
    EXPECT_LE(meanFlip, 1.0);
    if (s.at("method") == "uniform-2") {
      EXPECT_GT(meanFlip, 0.0) << s.dump();
      EXPECT_GT(flipFlicker, 0.0) << s.dump();
    }
  }
  const std::string csv = test::readFile(stabilityCsvPath(o.csvOut));
  EXPECT_EQ(stabilityCsvPath(o.csvOut), dir + "/bench-stability.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "path,scene,effect,samples,camera_path,frames,width,height,method,flicker,mean_rms,flip_flicker,mean_flip,"
            "expectation_flicker,expectation_mean_rms");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + static_cast<long>(j.at("stability").size()));
  const std::string md = test::readFile(o.markdownOut);
  EXPECT_NE(md.find("| flicker | mean RMS | FLIP flicker | mean FLIP |"), std::string::npos);
}

// --expectation K (SPEC §10): on SSAO each frame's error is also measured against full's mean over
// seeds 1..K, recomputed here from the same renders; SSM, which draws no noise, gets none; the
// camera paths get full's own row, steady against itself and not against the expectation.
TEST(BenchExpectation, IsFullsMeanOverTheOtherSeedsAndOnlyForNoisyEffects) {
  const std::string dir = test::scratchDir();
  BenchOptions o;
  o.scenes = {"builtin:demo"};
  o.sizes = {{48, 27}};
  o.effects = {"ssao", "ssm"};
  o.samples = {4};
  o.methods = {"full", "mrr"};
  o.cameras = 1;
  o.repeats = 1;
  o.paperSweeps = false;
  o.frames = 3;
  o.stabilitySize = {48, 27};
  o.stabilityScenes = {"builtin:demo"};
  o.stressScenes = {};
  o.expectationSeeds = 3;
  o.jsonOut = dir + "/bench.json";
  o.markdownOut = dir + "/bench.md";
  const BenchPath cpu = oracleBenchPath();
  std::ostringstream out;
  ASSERT_EQ(runBench(o, {cpu}, out), 0);
  const nlohmann::json j = nlohmann::json::parse(test::readFile(o.jsonOut));

  // The expectation as its definition says, from the bench's own camera and settings.
  const OpenScene sc = openScene("builtin:demo", cpu);
  const Camera camera = benchCameras(sc.camera, 1)[0];
  const float framed = framedSize(*sc.scene, camera, 48.0f / 27.0f).size;
  Settings s = settingsFor("full", Effect::Ssao, 48, 27, 4);
  const ImageF full = sc.render(camera, makeConstants(s, framed), {false, {}, nullptr}).final();
  ImageF mean(full.width, full.height, full.channels, 0.0f);
  for (uint32_t k = 1; k <= 3; ++k) {
    s.seed = k;
    const ImageF draw = sc.render(camera, makeConstants(s, framed), {false, {}, nullptr}).final();
    for (size_t i = 0; i < mean.data.size(); ++i) mean.data[i] += draw.data[i];
  }
  for (float& v : mean.data) v /= 3.0f;
  const double fullNoise = rmsError(full, mean);
  ASSERT_GT(fullNoise, 1e-3) << "4 samples a pixel: full is one noisy draw";

  int ssao = 0;
  for (const nlohmann::json& r : j.at("runs")) {
    if (r.at("effect") == "ssm") {
      EXPECT_FALSE(r.contains("rms_expectation")) << "SSM draws no noise: " << r.dump();
      continue;
    }
    ++ssao;
    ASSERT_TRUE(r.contains("rms_expectation")) << r.dump();
    const double e = r.at("rms_expectation").get<double>(), mae = r.at("mae_expectation").get<double>();
    EXPECT_GT(e, 0.0);
    EXPECT_LE(mae, e + 1e-12) << "a mean |Δ| is at most the RMS";
    if (r.at("method") == "full") EXPECT_NEAR(e, fullNoise, 1e-9 + 1e-6 * fullNoise) << "full against the mean of seeds 1..3";
  }
  EXPECT_EQ(ssao, 2);

  int fullRows = 0;
  for (const nlohmann::json& st : j.at("stability")) {
    ASSERT_TRUE(st.contains("expectation_flicker")) << st.dump();
    EXPECT_GT(st.at("expectation_mean_rms").get<double>(), 0.0) << st.dump();
    if (st.at("method") != "full") continue;
    ++fullRows;
    EXPECT_EQ(st.at("flicker").get<double>(), 0.0) << "full against itself";
    EXPECT_GT(st.at("expectation_flicker").get<double>(), 0.0) << "its noise moves with the camera";
  }
  EXPECT_EQ(fullRows, static_cast<int>(cameraPathKinds().size()));
  const std::string md = test::readFile(o.markdownOut);
  EXPECT_NE(md.find("### Error against the effect's expectation"), std::string::npos);
  EXPECT_NE(md.find("### Stability against the effect's expectation"), std::string::npos);
}

}  // namespace
}  // namespace mrr
