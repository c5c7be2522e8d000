#pragma once
// Charts for `mrr bench`, drawn by mrr itself (no plotting dependency): one Chart model,
// written as hand-made SVG text or rasterised to PNG with OpenImageIO's ImageBufAlgo, both in
// matplotlib's default look (white background, light grey grid, the tab10 palette).
//
// Both renderers draw from one Layout (plot area, axis ranges, ticks), so a data point lands
// on the same pixel in the SVG and the PNG (up to the PNG's y-axis label, which sits above
// the plot because render_text cannot rotate text).
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace mrr::chart {

// Every member has a default initializer (`{}` at least), so callers may brace-initialise a
// prefix, e.g. Point{x, y}, without -Wextra's missing-field-initializers warning.

struct Point {
  double x = 0, y = 0;
  std::string label{};  // shown as an SVG <title> tooltip when hovering the point; empty: none
};

enum class Marker { Circle, Square, Triangle, Diamond, Cross, None };

struct Series {
  std::string name{};  // legend entry (series with an empty name are not in the legend)
  std::vector<Point> points{};
  bool line = false;    // join the points, in order, with a polyline
  bool dashed = false;  // dashed line
  Marker marker = Marker::Circle;
  bool hollow = false;  // open markers (an outline around a white inside), e.g. for the paper's figures
  std::string color{};  // "#rrggbb"; empty: the palette (tab10) colour of this series' index
  // Bars from 0 (or the bottom of a log axis) to y. The bar series of a chart share 80% of the
  // slot at each x (a category, or the smallest x spacing), side by side in series order.
  bool bars = false;
};

struct Axis {
  std::string label{};  // with its unit, e.g. "time (ms)"
  bool log = false;     // log10 scale; non-positive values are not drawn
  std::optional<double> min{}, max{};  // fixed ends; empty: from the data (and guides), padded 5%
};

// A reference line across the plot, e.g. y = 1 labelled "full".
struct Guide {
  double value = 0;
  bool vertical = false;  // x = value (else y = value)
  std::string label{};
};

struct Chart {
  std::string title{}, subtitle{};  // subtitle: small grey line under the title (e.g. the machine)
  Axis x{}, y{};
  // Non-empty: the x axis is categorical; point.x is the category index, and bar series are
  // drawn as grouped bars side by side per category.
  std::vector<std::string> categories{};
  std::vector<Series> series{};
  std::vector<Guide> guides{};
  int width = 880, height = 560;  // pixels (SVG user units and PNG size)
};

// The SVG document (UTF-8 XML).
std::string toSvg(const Chart& chart);

// Both write atomically (a temporary file in the same directory, renamed into place) and throw
// mrr::MrrError with a one-line message on failure, leaving no file behind. writePng needs the
// DejaVu Sans fonts (Debian package fonts-dejavu-core).
void writeSvg(const Chart& chart, const std::string& path);
void writePng(const Chart& chart, const std::string& path);

// Indices of the Pareto-optimal points when x is to be minimised and y maximised (x = RMS
// error, y = speedup): a point is dropped when another has x <= and y >= with at least one
// strict (so exact duplicates both stay). Points with a non-finite coordinate are dropped.
// Sorted by x, then by y descending, then by index.
std::vector<size_t> paretoFront(const std::vector<Point>& points);

// --- Where things go, exposed so tests can find a data point in the rendered image. ---------

enum class Target { Svg, Png };

// One axis: the data range shown and its ticks. Pixel coordinates have the origin at the
// top-left corner of the image, y down, pixel centres at +0.5 (SVG's convention).
struct Scale {
  double lo = 0, hi = 1;            // data range at the ends of the axis (data units, even on a log axis)
  bool log = false;
  double pixelLo = 0, pixelHi = 1;  // pixel coordinate of lo and hi (y: pixelLo is the bottom)
  std::vector<double> ticks;        // data values (category indices on a categorical axis)
  std::vector<std::string> labels;  // one per tick, e.g. "0.001", "1.5", "1e-4", or the category
  std::vector<double> minorTicks;   // log axes: the other multiples of each decade (short, unlabelled)
  // Pixel coordinate of a data value; empty when it cannot be drawn (not finite, or <= 0 on a
  // log axis). Values outside [lo, hi] map outside the plot area.
  std::optional<double> toPixel(double value) const;
};

struct Layout {
  double left = 0, top = 0, right = 0, bottom = 0;  // the plot area, in pixels
  Scale x, y;
  std::optional<std::array<double, 2>> toPixel(double x, double y) const;
};

// The layout `target` draws `chart` with (they differ only in room for the y-axis label).
// Throws MrrError for a chart that cannot be drawn (bad colour, size out of range).
Layout layoutOf(const Chart& chart, Target target);

}  // namespace mrr::chart
