// The two report pages and the bench's charts, made by compare/report/report.py (matplotlib and
// Jinja2) from what C++ hands it: the files exist and are what they claim to be, the pages show
// the rows, figures and worst pixels, and a missing or failing Python is one clear error.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "common/error.h"
#include "common/params.h"
#include "compare/bench/bench_report.h"
#include "compare/metrics/flip.h"
#include "compare/parity/html_report.h"
#include "compare/parity/parity.h"
#include "compare/report/report_python.h"
#include "cpu_ref/pipeline.h"
#include "scenes/catalog.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mrr {
namespace {

std::string readFile(const fs::path& path) { return test::readFile(path.string()); }

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

std::set<std::string> filesIn(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

// Sets an environment variable for one test and puts the old value back.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) setenv(name_, old_->c_str(), 1);
    else unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

BenchRecord record(const std::string& group, const std::string& scene, int camera, const std::string& method,
                   int width, int height, int samples, double speedup, double rms) {
  BenchRecord r;
  r.path = "cpu";
  r.scene = scene;
  r.group = group;
  r.method = method;
  r.effect = "ssao";
  r.camera = camera;
  r.width = width;
  r.height = height;
  r.samples = samples;
  r.measuredSpeedup = method == "full" ? 1.0 : speedup;
  r.idealSpeedup = method == "full" ? 1.0 : 1.5 * speedup;
  r.fullEffectMs = 20.0;
  r.effectMs = 20.0 / r.measuredSpeedup;
  r.shadedPixels = static_cast<long long>(width * height / r.idealSpeedup);
  r.error.rms = method == "full" ? 0.0 : rms;
  r.flip = method == "full" ? 0.0 : 3.0 * rms;
  r.error.ssim = 0.99;
  return r;
}

// Every group the bench measures, on one path and one effect, small enough to draw fast.
BenchResults syntheticBench() {
  BenchResults res;
  res.options.machine = "a test machine";
  res.options.repeats = 3;
  res.devices["cpu"] = "cpu_ref (oracle), 2 threads";
  res.threads = 2;
  for (const std::string scene : {"builtin:demo", "arcade"})
    for (int camera = 0; camera < 2; ++camera)
      for (const auto& [method, speedup, rms] : {std::tuple<std::string, double, double>{"full", 1.0, 0.0},
                                                 {"uniform-1", 3.0, 0.01},
                                                 {"tiles", 1.8, 0.002},
                                                 {"mrr", 2.2, 0.001 * (camera + 1)}})
        res.records.push_back(record("main", scene, camera, method, 320, 180, 64, speedup, rms));
  for (int samples : {16, 64})
    for (const std::string method : {"full", "mrr"})
      res.records.push_back(record("samples", "builtin:demo", 0, method, 320, 180, samples, 1.0 + samples / 32.0, 0.002));
  for (int height : {360, 720})
    for (const std::string method : {"full", "mrr"})
      res.records.push_back(record("resolution", "builtin:demo", 0, method, height * 16 / 9, height, 64, height / 90.0, 0.003));
  for (const std::string scene : {"builtin:bumpy", "builtin:wires"})
    for (const std::string method : {"full", "mrr", "mrr-norule"})
      res.records.push_back(record("stress", scene, 0, method, 320, 180, 64, 0.9, 0.0));
  for (const std::string method : {"uniform-1", "mrr"}) {
    StabilityRecord s;
    s.path = "cpu";
    s.scene = "builtin:demo";
    s.effect = "ssao";
    s.samples = 64;
    s.kind = "orbit";
    s.frames = 8;
    s.width = 160;
    s.height = 90;
    s.method = method;
    s.flicker = method == "mrr" ? 0.0005 : 0.005;
    s.meanRms = 0.01;
    s.flipFlicker = method == "mrr" ? 0.0025 : 0.0375;
    s.meanFlip = method == "mrr" ? 0.02 : 0.09;
    res.stability.push_back(s);
  }
  return res;
}

const std::vector<std::string> kBenchCharts = {"speed-vs-rms-cpu-ssao", "speed-vs-flip-cpu-ssao", "fig6-cpu-ssao",
                                               "fig7-cpu-ssao",         "fig9-cpu-ssao",          "stress-cpu-ssao",
                                               "flicker-cpu",           "flicker-cpu-flip"};

TEST(BenchReportTest, DrawsEveryChartAsSvgAndPngAndThePageShowsThemWithTheTables) {
  const fs::path dir = test::scratchDir();
  const fs::path paper = dir / "paper-figures.csv";
  std::ofstream(paper) << "# the paper's figures, a few\nfigure,effect,samples,width,height,speedup_pct,rms\n"
                          "fig6,ssao,64,3840,2160,126,\nfig7,ssao,64,1280,720,28.7,\nfig9,ssao,64,1280,720,,0.0083\n";
  const ScopedEnv paperFigures("MRR_PAPER_FIGURES", paper.string());
  const fs::path out = dir / "report";
  fs::create_directories(out);
  writeBenchReport(out.string(), syntheticBench(), {"cpu arcade camera 1: <b>made up</b> & planted"});

  std::set<std::string> expected = {};
  for (const std::string& name : kBenchCharts) expected.insert({name + ".svg", name + ".png"});
  EXPECT_EQ(filesIn(out / "charts"), expected) << "one SVG and one PNG per chart, no temporary left";
  EXPECT_EQ(filesIn(out), (std::set<std::string>{"charts", "index.html"}));
  for (const std::string& name : kBenchCharts) {
    const std::string svg = readFile(out / "charts" / (name + ".svg"));
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u) << name;
    EXPECT_NE(svg.find("<svg "), std::string::npos) << name;
    EXPECT_NE(svg.find("</svg>"), std::string::npos) << name << ": the SVG is cut short";
    auto png = OIIO::ImageInput::open((out / "charts" / (name + ".png")).string());
    ASSERT_TRUE(png) << name << ": " << OIIO::geterror();
    EXPECT_EQ(png->spec().width, 880) << name;
    EXPECT_EQ(png->spec().height, 560) << name;
  }
  // matplotlib writes each text of an SVG (drawn as paths) as a comment: the legends are there.
  EXPECT_NE(readFile(out / "charts" / "fig7-cpu-ssao.svg").find("paper, Fig. 7 (GTX 1080, top axis)"), std::string::npos);
  EXPECT_NE(readFile(out / "charts" / "fig6-cpu-ssao.svg").find("paper, Fig. 6 (GTX 1080, at 4K)"), std::string::npos);
  EXPECT_NE(readFile(out / "charts" / "fig9-cpu-ssao.svg").find("paper, Fig. 9 (GTX 1080, top axis)"), std::string::npos);
  EXPECT_NE(readFile(out / "charts" / "speed-vs-rms-cpu-ssao.svg").find("Pareto front"), std::string::npos);
  EXPECT_NE(readFile(out / "charts" / "stress-cpu-ssao.svg").find("mrr-norule"), std::string::npos);
  EXPECT_NE(readFile(out / "charts" / "flicker-cpu-flip.svg").find("FLIP flicker"), std::string::npos);

  const std::string page = readFile(out / "index.html");
  for (const std::string& name : kBenchCharts) {
    EXPECT_NE(page.find("<figure id=\"" + name + "\"><img class=\"chart\" src=\"charts/" + name + ".svg\""),
              std::string::npos)
        << name;
    EXPECT_NE(page.find("href=\"charts/" + name + ".png\""), std::string::npos) << name;
  }
  EXPECT_EQ(count(page, "<figure id="), kBenchCharts.size());
  // The sanity failure, escaped; the tables of bench_report.cpp, with the paper beside mrr.
  EXPECT_NE(page.find("<ul class=\"fail\" id=\"sanity\"><li>cpu arcade camera 1: &lt;b&gt;made up&lt;/b&gt; &amp; planted</li>"),
            std::string::npos);
  EXPECT_NE(page.find("<h3>Per scene (median over cameras)</h3>"), std::string::npos);
  EXPECT_NE(page.find("<td>arcade</td><td>ssao</td><td>mrr</td><td>2.20x</td>"), std::string::npos);
  // FLIP beside RMS in the main and the per-scene tables: mrr's RMS over the arcade's two cameras
  // is 0.001 and 0.002 (median 0.0015), its FLIP three times that.
  EXPECT_EQ(count(page, "<th>FLIP</th>"), 2u);
  EXPECT_NE(page.find("<td>arcade</td><td>ssao</td><td>mrr</td><td>2.20x</td><td>3.30x</td><td>0.0015</td><td>0.0045</td>"),
            std::string::npos);
  EXPECT_NE(page.find("<td>1.29x</td>"), std::string::npos) << "the paper's Fig. 7 speedup at 720p, beside mrr";
  // The stability table carries FLIP beside RMS: flicker, mean RMS, FLIP flicker, mean FLIP.
  EXPECT_NE(page.find("<th>FLIP flicker</th>"), std::string::npos);
  EXPECT_NE(page.find("<td>mrr</td><td>0.0005</td><td>0.01</td><td>0.0025</td><td>0.02</td>"),
            std::string::npos);
  EXPECT_EQ(page.find("The paper's figures were not found"), std::string::npos);
  EXPECT_NE(page.find("document.body.dataset.loaded"), std::string::npos);
}

TEST(BenchReportTest, SaysAllPassedAndWhenThePapersFiguresAreMissing) {
  const fs::path dir = test::scratchDir();
  const ScopedEnv paperFigures("MRR_PAPER_FIGURES", (dir / "none.csv").string());
  writeBenchReport(dir.string(), syntheticBench(), {});
  const std::string page = readFile(dir / "index.html");
  EXPECT_NE(page.find("<p class=\"ok\" id=\"sanity\">All passed.</p>"), std::string::npos);
  EXPECT_NE(page.find("The paper's figures were not found (" + (dir / "none.csv").string() + ")"), std::string::npos);
  EXPECT_EQ(readFile(dir / "charts" / "fig7-cpu-ssao.svg").find("paper, Fig. 7"), std::string::npos);
}

// The oracle against a copy of itself with one final pixel planted: the page must name the
// final stage as the first failure, show its trio, and give the probe command for that pixel.
TEST(CompareReportTest, ShowsEveryStageAndTheWorstPixelWithItsProbeCommand) {
  Settings s = defaultSettings(Effect::Ssao);
  s.width = 64;
  s.height = 36;
  s.ssao.samples = 4;
  s.neverSlower = false;
  SceneRequest request;
  request.scene = "builtin:demo";
  const ResolvedScene rs = resolveScene(request);
  const Renderer renderer(rs.scene);
  const FrameResult oracle = renderer.render(rs.camera, makeConstants(s, rs.framed.size));
  FrameResult port = oracle;
  port.blend.final.at(41, 17) -= 0.5f;  // down: an unoccluded 1 + 0.5 would clamp to 1, invisible to FLIP
  const ParityResult result = compareFrames(oracle, port, rs.scene.light);
  ASSERT_EQ(result.firstFailing(), "final");

  const fs::path dir = test::scratchDir();
  const std::string probe = "mrr probe --path both --scene builtin:demo --effect ssao --size 64x36 --samples 4";
  writeCompareReport(dir.string(), {"builtin:demo", "Made by <someone> & co.", "a planted port", "mrr compare …"},
                     {{"ssao", &oracle, &port, result, probe}});
  EXPECT_EQ(filesIn(dir), std::set<std::string>{"index.html"}) << "one page, nothing else";
  const std::string page = readFile(dir / "index.html");

  EXPECT_EQ(count(page, "<section class=\"stage "), result.rows.size());
  for (const StageRow& row : result.rows)
    EXPECT_NE(page.find("id=\"ssao-" + row.stage + "\" data-effect=\"ssao\" data-stage=\"" + row.stage +
                        "\" data-verdict=\"" + row.verdict() + "\""),
              std::string::npos)
        << row.stage;
  EXPECT_NE(page.find("<h2 id=\"ssao-summary\">"), std::string::npos);
  EXPECT_NE(page.find("first failing stage <a href=\"#ssao-final\"><b>final</b></a>"), std::string::npos);
  EXPECT_NE(page.find("<code class=\"cmd\">" + probe + " --pixel 41,17</code>"), std::string::npos);
  EXPECT_NE(page.find("<b>41,17</b>"), std::string::npos);
  EXPECT_NE(page.find("Scene credit: Made by &lt;someone&gt; &amp; co."), std::string::npos);
  // The FLIP map of the final image beside its |Δ| (in the overview and its section) and of the
  // shaded one, with the magma scale and the mean: the planted pixel's, and 0 for the untouched
  // shaded image.
  const FlipStats planted = flip(oracle.final(), port.final()).stats;
  ASSERT_GT(planted.mean, 0.0);
  char mean[32];
  std::snprintf(mean, sizeof mean, "%.3g", planted.mean);
  EXPECT_EQ(count(page, "<figure class=\"flip\">"), 3u);
  EXPECT_EQ(count(page, "mean <b class=\"flip-mean\">" + std::string(mean) + "</b>"), 2u) << mean;
  const size_t shaded = page.find("id=\"ssao-shaded\"");
  ASSERT_NE(shaded, std::string::npos);
  EXPECT_NE(page.find("mean <b class=\"flip-mean\">0</b>, max 0:", shaded), std::string::npos);
  EXPECT_NE(page.find(".ramp.magma{background:linear-gradient(to right,rgb(0,0,4)"), std::string::npos);
  // Self-contained: every image is an embedded PNG, nothing is fetched.
  const size_t images = count(page, "<img ");
  EXPECT_GT(images, 3 * result.rows.size() / 2);
  EXPECT_EQ(count(page, "<img src=\"data:image/png;base64,iVBORw0KGgo"), images);
  EXPECT_EQ(page.find("src=\"http"), std::string::npos);
  EXPECT_EQ(page.find("href=\"http"), std::string::npos);
}

TEST(ReportPythonTest, AMissingInterpreterIsOneClearError) {
  const ScopedEnv python("MRR_PYTHON", "/nonexistent/python3");
  try {
    requireReportPython();
    FAIL() << "no error";
  } catch (const MrrError& e) {
    EXPECT_STREQ(e.what(),
                 "--report needs matplotlib and Jinja2 (Debian: apt-get install python3-matplotlib python3-jinja2)");
  }
}

// An interpreter that has the packages but whose run fails: the error names Python's last line,
// and no page is left behind.
TEST(ReportPythonTest, AFailingRunNamesPythonsLastLineAndWritesNoPage) {
  const fs::path dir = test::scratchDir();
  const fs::path fake = dir / "python3";
  std::ofstream(fake) << "#!/bin/sh\n[ \"$1\" = -c ] && exit 0\necho 'Traceback (most recent call last):' >&2\n"
                         "echo 'ValueError: planted failure' >&2\nexit 1\n";
  fs::permissions(fake, fs::perms::owner_all);
  const ScopedEnv python("MRR_PYTHON", fake.string());
  EXPECT_NO_THROW(requireReportPython());
  const fs::path out = dir / "report";
  fs::create_directories(out);
  try {
    writeBenchReport(out.string(), syntheticBench(), {});
    FAIL() << "no error";
  } catch (const MrrError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("ValueError: planted failure"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(out / "index.html"));
  EXPECT_EQ(filesIn(out), std::set<std::string>{});
}

}  // namespace
}  // namespace mrr
