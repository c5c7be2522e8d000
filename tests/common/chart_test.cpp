#include "compare/chart.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "common/error.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace mrr::chart {
namespace {

// The inside of a marker or bar is drawn in the series colour at every supersample, so the
// downsampled pixel is that colour up to 8-bit rounding; 3/255 leaves room for one level of
// rounding in each direction and nothing else.
constexpr double kColourTolerance = 3.0 / 255.0;

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

// Enough of XML to catch what a hand-written emitter gets wrong: every tag closes, in order,
// under one root; no raw '<' inside a tag; every '&' starts one of the entities we write;
// attribute quotes are balanced.
::testing::AssertionResult wellFormed(const std::string& xml) {
  std::vector<std::string> open;
  int roots = 0;
  const auto entityAt = [&](size_t i) {
    for (const char* e : {"&amp;", "&lt;", "&gt;", "&quot;", "&#39;"})
      if (xml.compare(i, std::string(e).size(), e) == 0) return true;
    return false;
  };
  for (size_t i = 0; i < xml.size(); ++i) {
    if (xml[i] == '&' && !entityAt(i)) return ::testing::AssertionFailure() << "bare & at " << i;
    if (xml[i] != '<') continue;
    const size_t end = xml.find('>', i);
    if (end == std::string::npos) return ::testing::AssertionFailure() << "unclosed tag at " << i;
    const std::string tag = xml.substr(i + 1, end - i - 1);
    if (tag.find('<') != std::string::npos) return ::testing::AssertionFailure() << "'<' inside tag at " << i;
    if (std::count(tag.begin(), tag.end(), '"') % 2 != 0)
      return ::testing::AssertionFailure() << "unbalanced quotes in <" << tag << ">";
    if (tag.empty()) return ::testing::AssertionFailure() << "empty tag at " << i;
    if (tag[0] == '?') {
      if (i != 0) return ::testing::AssertionFailure() << "declaration not at the start";
    } else if (tag[0] == '/') {
      if (open.empty() || open.back() != tag.substr(1))
        return ::testing::AssertionFailure() << "</" << tag.substr(1) << "> closes "
                                             << (open.empty() ? std::string("nothing") : "<" + open.back() + ">");
      open.pop_back();
    } else {
      if (open.empty()) ++roots;
      if (tag.back() != '/') open.push_back(tag.substr(0, tag.find_first_of(" \n/")));
    }
    i = end;
  }
  if (!open.empty()) return ::testing::AssertionFailure() << "<" << open.back() << "> never closes";
  if (roots != 1) return ::testing::AssertionFailure() << roots << " root elements";
  return ::testing::AssertionSuccess();
}

// The shape of the bench's main figure: error against speedup, a Pareto line, a guide.
Chart scatterChart() {
  Chart c;
  c.title = "SSAO: speedup vs error";
  c.subtitle = "arcade, 1280x720";
  c.x = {"RMS error vs full", true, {}, {}};
  c.y = {"speedup (x)", false, {}, {}};
  Series measured{"multires", {}, false, false, Marker::Circle};
  measured.points = {{0.0008, 2.1, "16 samples"}, {0.002, 3.4, "64 samples"}, {0.004, 2.9, ""}, {0.02, 4.2, "256 samples"}};
  Series front{"Pareto front", {}, true, true, Marker::None};
  for (const size_t i : paretoFront(measured.points)) front.points.push_back(measured.points[i]);
  c.series = {measured, front};
  c.guides = {{1, false, "full"}};
  return c;
}

Chart barChart() {
  Chart c;
  c.title = "Stage times";
  c.y.label = "time (ms)";
  c.categories = {"gbuffer", "edges", "ssao", "blend"};
  Series full{"full", {{0, 3}, {1, 1}, {2, 20}, {3, 1.5}}};
  full.bars = true;
  Series multires{"multires", {{0, 3.1}, {1, 1.2}, {2, 6}, {3, 2}}};
  multires.bars = true;
  c.series = {full, multires};
  return c;
}

struct Png {
  int width = 0, height = 0, channels = 0;
  OIIO::TypeDesc format;
  std::vector<float> pixels;
  std::array<float, 3> at(int x, int y) const {
    const size_t i = (static_cast<size_t>(y) * width + x) * 3;
    return {pixels[i], pixels[i + 1], pixels[i + 2]};
  }
};

Png readPng(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw MrrError("cannot open " + path);
  Png png;
  png.width = in->spec().width;
  png.height = in->spec().height;
  png.channels = in->spec().nchannels;
  png.format = in->spec().format;
  png.pixels.resize(static_cast<size_t>(png.width) * png.height * 3);
  in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, png.pixels.data());
  in->close();
  return png;
}

std::array<float, 3> rgbOf(const std::string& hex) {
  const auto channel = [&](size_t at) { return static_cast<float>(std::stoi(hex.substr(at, 2), nullptr, 16)) / 255.0f; };
  return {channel(1), channel(3), channel(5)};
}

::testing::AssertionResult colourNear(const std::array<float, 3>& got, const std::string& want) {
  const std::array<float, 3> w = rgbOf(want);
  for (int c = 0; c < 3; ++c)
    if (std::fabs(got[c] - w[c]) > kColourTolerance)
      return ::testing::AssertionFailure() << "got (" << got[0] * 255 << ", " << got[1] * 255 << ", " << got[2] * 255
                                           << "), want " << want;
  return ::testing::AssertionSuccess();
}

std::vector<std::string> listDir(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ChartPareto, DropsDominatedPointsSortedByX) {
  // (x to minimise, y to maximise)
  const std::vector<Point> points = {{3, 5}, {1, 1}, {2, 4}, {2.5, 3}, {4, 4.5}, {0.5, 0.5}, {5, 6}};
  // (2.5, 3) is beaten by (2, 4); (4, 4.5) by (3, 5); the others trade x against y.
  EXPECT_EQ(paretoFront(points), (std::vector<size_t>{5, 1, 2, 0, 6}));
}

TEST(ChartPareto, TiesNeedOneStrictImprovementToDominate) {
  const std::vector<Point> points = {
      {1, 2},                // 0: kept
      {1, 3},                // 1: same x, higher y: beats 0
      {2, 3},                // 2: same y as 1, larger x: beaten by 1
      {4, 7}, {4, 7},        // 3, 4: exact duplicates: neither is strictly better, both stay
      {NAN, 9}, {0.1, INFINITY},  // 5, 6: not finite: dropped, and beat nothing
  };
  EXPECT_EQ(paretoFront(points), (std::vector<size_t>{1, 3, 4}));
  EXPECT_TRUE(paretoFront({}).empty());
  EXPECT_EQ(paretoFront({{7, 7}}), (std::vector<size_t>{0}));
}

TEST(ChartSvg, HasSizeTitleAxisLabelsAndLegend) {
  const Chart chart = scatterChart();
  const std::string svg = toSvg(chart);
  EXPECT_TRUE(wellFormed(svg));
  EXPECT_NE(svg.find("width=\"880\" height=\"560\" viewBox=\"0 0 880 560\""), std::string::npos);
  EXPECT_NE(svg.find("font-family=\"DejaVu Sans, Arial, sans-serif\""), std::string::npos);
  for (const std::string& text : {chart.title, chart.subtitle, chart.x.label, chart.y.label, std::string("multires"),
                                  std::string("Pareto front"), std::string("full")})
    EXPECT_NE(svg.find(">" + text + "</text>"), std::string::npos) << text;
  // The y label is rotated in SVG (the PNG puts it above the plot instead).
  EXPECT_NE(svg.find("transform=\"rotate(-90"), std::string::npos);
}

TEST(ChartSvg, EscapesSpecialCharactersEverywhere) {
  Chart chart;
  const std::string nasty = "a<b & \"c\"";
  const std::string escaped = "a&lt;b &amp; &quot;c&quot;";
  chart.title = nasty;
  chart.subtitle = nasty;
  chart.x.label = nasty;
  chart.y.label = nasty;
  chart.categories = {nasty, "plain"};
  chart.series = {{nasty, {{0, 1, nasty}, {1, 2, ""}}}};
  chart.guides = {{1.5, false, nasty}};
  const std::string svg = toSvg(chart);
  EXPECT_TRUE(wellFormed(svg));
  EXPECT_EQ(count(svg, nasty), 0u);
  // title, subtitle, two axis labels, a category, the legend, the tooltip, the guide
  EXPECT_EQ(count(svg, escaped), 8u);
}

TEST(ChartSvg, OneTooltipPerLabelledPoint) {
  Chart chart = scatterChart();
  const std::string svg = toSvg(chart);
  // Three labelled measured points, and the same three again on the Pareto front line (its
  // Marker::None points carry invisible hover targets).
  size_t labelled = 0;
  for (const Series& s : chart.series)
    for (const Point& p : s.points) labelled += p.label.empty() ? 0 : 1;
  EXPECT_EQ(count(svg, "<title>"), labelled);
  EXPECT_EQ(count(svg, "</title>"), labelled);
  EXPECT_NE(svg.find("<title>64 samples</title>"), std::string::npos);
  // A labelled bar gets one as well.
  Chart bars = barChart();
  bars.series[0].points[2].label = "ssao: 20 ms";
  EXPECT_EQ(count(toSvg(bars), "<title>ssao: 20 ms</title>"), 1u);
}

TEST(ChartLayout, LinearTicksAreNiceStepsInsideTheRange) {
  Chart chart;
  chart.series = {{"s", {{0, 0}, {9.3, 0.37}}}};
  const Layout layout = layoutOf(chart, Target::Svg);
  for (const Scale* s : {&layout.x, &layout.y}) {
    ASSERT_GE(s->ticks.size(), 3u);
    ASSERT_EQ(s->ticks.size(), s->labels.size());
    const double step = s->ticks[1] - s->ticks[0];
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step)));
    EXPECT_TRUE(std::fabs(mantissa - 1) < 1e-9 || std::fabs(mantissa - 2) < 1e-9 || std::fabs(mantissa - 5) < 1e-9)
        << "step " << step;
    EXPECT_GE(s->ticks.front(), s->lo);
    EXPECT_LE(s->ticks.back(), s->hi);
    // Padded past the data, by a little.
    EXPECT_LT(s->lo, 0);
  }
  EXPECT_GT(layout.x.hi, 9.3);
  EXPECT_LT(layout.x.hi, 9.3 * 1.1);
  // Compact labels: no trailing zeros.
  for (const std::string& label : layout.y.labels) EXPECT_TRUE(label == "0" || label.back() != '0') << label;
  // Data maps into the plot area: y up, x right.
  const auto origin = layout.toPixel(0, 0), corner = layout.toPixel(9.3, 0.37);
  ASSERT_TRUE(origin && corner);
  EXPECT_GT((*origin)[0], layout.left);
  EXPECT_LT((*origin)[1], layout.bottom);
  EXPECT_LT((*corner)[0], layout.right);
  EXPECT_GT((*corner)[1], layout.top);
}

TEST(ChartLayout, ExplicitAxisEndsAreKept) {
  Chart chart;
  chart.series = {{"s", {{0.2, 0.3}, {0.8, 0.9}}}};
  chart.y.min = 0;
  chart.y.max = 1;
  const Layout layout = layoutOf(chart, Target::Png);
  EXPECT_EQ(layout.y.lo, 0);
  EXPECT_EQ(layout.y.hi, 1);
  EXPECT_EQ(layout.y.toPixel(0), layout.bottom);
  EXPECT_EQ(layout.y.toPixel(1), layout.top);
  chart.x.log = true;
  chart.x.min = -1;
  EXPECT_THROW(layoutOf(chart, Target::Svg), MrrError);
}

TEST(ChartLayout, LogAxisTicksAtPowersOfTen) {
  Chart chart;
  chart.x.log = true;
  chart.series = {{"errors", {{0.0005, 1}, {0.005, 2}, {0.05, 3}}}};
  const Layout layout = layoutOf(chart, Target::Svg);
  EXPECT_EQ(layout.x.labels, (std::vector<std::string>{"0.001", "0.01"}));
  const std::string svg = toSvg(chart);
  EXPECT_NE(svg.find(">0.001</text>"), std::string::npos);
  EXPECT_NE(svg.find(">0.01</text>"), std::string::npos);
  // Under two decades: 2 and 5 times the powers too; tiny values in exponent form.
  chart.series = {{"tiny", {{2e-5, 1}, {3e-4, 2}}}};
  const std::vector<std::string> labels = layoutOf(chart, Target::Svg).x.labels;
  for (const char* want : {"2e-5", "5e-5", "1e-4", "2e-4"})
    EXPECT_NE(std::find(labels.begin(), labels.end(), want), labels.end()) << want;
}

TEST(ChartLayout, LogAxisSkipsNonPositivePoints) {
  Chart chart;
  chart.x.log = true;
  chart.y.log = true;
  Series s{"s", {{0, 1, "zero x"}, {-1, 1, "negative x"}, {0.01, 0, "zero y"}, {0.01, 10, "drawn"}, {1, 100, "drawn too"}}};
  s.line = true;
  chart.series = {s};
  chart.guides = {{0, false, "y = 0 has no place on a log axis"}, {-2, true, "nor x = -2"}};
  const std::string svg = toSvg(chart);
  EXPECT_TRUE(wellFormed(svg));
  EXPECT_EQ(count(svg, "<title>"), 2u);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  EXPECT_EQ(svg.find("has no place"), std::string::npos);
  const Layout layout = layoutOf(chart, Target::Svg);
  EXPECT_GT(layout.x.lo, 0);
  EXPECT_FALSE(layout.toPixel(0, 1).has_value());
  EXPECT_FALSE(layout.toPixel(0.01, -3).has_value());
}

TEST(ChartSvg, EveryKindIsWellFormed) {
  Chart line;
  line.title = "Scaling";
  for (int k = 0; k < 6; ++k) {
    Series s{"series", {}, true, k % 2 == 1, static_cast<Marker>(k), k >= 3};
    s.name += std::to_string(k);  // appended, not "series" + ...: avoids GCC 12's false -Wrestrict
    for (int i = 0; i < 5; ++i) {
      s.points.push_back({double(i), double(i * k), "p"});
      s.points.back().label += std::to_string(i);
    }
    line.series.push_back(s);
  }
  line.guides = {{2, true, "vertical"}, {3, false, "horizontal"}};
  for (const Chart& chart : {scatterChart(), barChart(), line}) EXPECT_TRUE(wellFormed(toSvg(chart))) << chart.title;
}

TEST(ChartSvg, RejectsBadColour) {
  Chart chart;
  chart.series = {{"s", {{1, 1}}}};
  chart.series[0].color = "red\"/><script>";
  EXPECT_THROW(toSvg(chart), MrrError);
}

TEST(ChartPng, DrawsTheSeriesColourAtItsDataPoint) {
  Chart chart;
  chart.title = "One point";
  chart.x = {"x (units)", false, 0.0, 10.0};
  chart.y = {"y (units)", false, 0.0, 10.0};
  chart.width = 640;
  chart.height = 400;
  chart.series = {{"only", {{5, 5}}}, {"square", {{2, 7}}, false, false, Marker::Square, false, "#123456"}};
  const std::string path = test::scratchDir() + "/point.png";
  writePng(chart, path);
  const Png png = readPng(path);
  EXPECT_EQ(png.width, 640);
  EXPECT_EQ(png.height, 400);
  EXPECT_EQ(png.channels, 3);  // opaque RGB
  EXPECT_EQ(png.format, OIIO::TypeDesc::UINT8);

  size_t drawn = 0;
  for (const float v : png.pixels) drawn += v < 0.99f ? 1 : 0;
  EXPECT_GT(drawn, png.pixels.size() / 100) << "hardly anything drawn";
  EXPECT_TRUE(colourNear(png.at(0, 0), "#ffffff"));  // white background

  const Layout layout = layoutOf(chart, Target::Png);
  const auto centre = layout.toPixel(5, 5), square = layout.toPixel(2, 7);
  ASSERT_TRUE(centre && square);
  EXPECT_TRUE(colourNear(png.at(int((*centre)[0]), int((*centre)[1])), "#1f77b4"));  // tab10's first colour
  EXPECT_TRUE(colourNear(png.at(int((*square)[0]), int((*square)[1])), "#123456"));
  // A marker is a few pixels across, not a blob: 10 pixels off is background again.
  EXPECT_TRUE(colourNear(png.at(int((*centre)[0]) + 10, int((*centre)[1]) + 10), "#ffffff"));
}

TEST(ChartPng, CategoricalBarsAreGroupedSideBySide) {
  const Chart chart = barChart();
  const std::string path = test::scratchDir() + "/bars.png";
  writePng(chart, path);
  const Png png = readPng(path);
  ASSERT_EQ(png.width, chart.width);
  ASSERT_EQ(png.height, chart.height);
  // Two bar series share 80% of a slot: series 0 centred at index - 0.2, series 1 at + 0.2.
  const Layout layout = layoutOf(chart, Target::Png);
  for (const auto& [series, offset, colour] : {std::tuple{0, -0.2, "#1f77b4"}, std::tuple{1, 0.2, "#ff7f0e"}}) {
    const Point& p = chart.series[static_cast<size_t>(series)].points[1];
    const auto middle = layout.toPixel(p.x + offset, p.y / 2);
    ASSERT_TRUE(middle);
    EXPECT_TRUE(colourNear(png.at(int((*middle)[0]), int((*middle)[1])), colour)) << "series " << series;
  }
  // Bars start at 0, which sits on the bottom of the axis.
  EXPECT_EQ(layout.y.lo, 0);
}

TEST(ChartWrite, SvgFileHoldsTheDocument) {
  const Chart chart = scatterChart();
  const std::string path = test::scratchDir() + "/chart.svg";
  writeSvg(chart, path);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), toSvg(chart));
}

TEST(ChartWrite, UnwritablePathThrowsAndLeavesNoFile) {
  const Chart chart = scatterChart();
  EXPECT_THROW(writePng(chart, "/nonexistent-dir/x.png"), MrrError);
  EXPECT_THROW(writeSvg(chart, "/nonexistent-dir/x.svg"), MrrError);
  EXPECT_FALSE(fs::exists("/nonexistent-dir"));
  // A path that is a directory: refused, and no temporary file is left beside it.
  const std::string dir = test::scratchDir();
  fs::create_directory(dir + "/taken.png");
  fs::create_directory(dir + "/taken.svg");
  EXPECT_THROW(writePng(chart, dir + "/taken.png"), MrrError);
  EXPECT_THROW(writeSvg(chart, dir + "/taken.svg"), MrrError);
  EXPECT_EQ(listDir(dir), (std::vector<std::string>{"taken.png", "taken.svg"}));
  // The wrong extension is refused before anything is written.
  EXPECT_THROW(writePng(chart, dir + "/chart.svg"), MrrError);
  EXPECT_THROW(writeSvg(chart, dir + "/chart.png"), MrrError);
  EXPECT_EQ(listDir(dir), (std::vector<std::string>{"taken.png", "taken.svg"}));
}

}  // namespace
}  // namespace mrr::chart
