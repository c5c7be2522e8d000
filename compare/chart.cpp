#include "compare/chart.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string_view>

#include "common/error.h"
#include "common/image.h"
#include "common/image_io.h"

namespace fs = std::filesystem;

namespace mrr::chart {

namespace {

// ---------------------------------------------------------------------------------------------
// The look, in pixels of the output (the PNG is drawn at kSupersample× and downsampled).
// Sizes follow matplotlib's defaults at 100 dpi, a little larger for the title.

constexpr std::array<const char*, 10> kPalette = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                  "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};  // tab10
constexpr double kPad = 14;  // empty border around everything
constexpr double kTitleSize = 15, kSubtitleSize = 11.5, kLabelSize = 13, kTickSize = 11.5;
constexpr double kLegendSize = 12, kGuideSize = 10.5;
constexpr double kLineHeight = 1.3;  // text line advance, in font sizes
// DejaVu Sans: capitals reach 0.73 em above the baseline, descenders 0.24 em below. Text is
// placed by its baseline everywhere, so the SVG and PNG agree without font metrics.
constexpr double kAscent = 0.76, kDescent = 0.24, kMidCap = 0.36;
constexpr double kTickLength = 4, kMinorTickLength = 2.5, kTickGap = 3;
constexpr double kMarkerRadius = 4.5;
constexpr double kLineWidth = 2, kHollowStroke = 1.5, kCrossStroke = 1.8;
constexpr double kSeriesDash[2] = {6, 3.5}, kGuideDash[2] = {4, 3};
constexpr double kMargin = 0.05;        // share of the data span added at each end of an axis
constexpr double kBarGroupShare = 0.8;  // share of a category's slot its bars fill
constexpr int kSupersample = 2;

constexpr const char* kBackground = "#ffffff";
constexpr const char* kGridColor = "#e5e5e5";
constexpr const char* kFrameColor = "#4d4d4d";
constexpr const char* kTextColor = "#222222";
constexpr const char* kTickTextColor = "#444444";
constexpr const char* kSubtitleColor = "#777777";
constexpr const char* kGuideColor = "#8c8c8c";
constexpr const char* kLegendBorder = "#d0d0d0";
constexpr double kLegendOpacity = 0.85;

constexpr const char* kFontFamily = "DejaVu Sans, Arial, sans-serif";
constexpr const char* kFontFile = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
constexpr const char* kBoldFontFile = "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf";
constexpr const char* kFontPackage = "fonts-dejavu-core";

// ---------------------------------------------------------------------------------------------
// Text: widths without font files (DejaVu Sans advance widths, in 1/2048 em), so the layout
// is the same for both outputs and needs no font to write SVG.

constexpr std::array<int, 95> kAdvance = {
    651,  821,  942,  1716, 1303, 1946, 1597, 563,  799,  799,  1024, 1716, 651,  739,  651,  690,   // ' '../
    1303, 1303, 1303, 1303, 1303, 1303, 1303, 1303, 1303, 1303, 690,  690,  1716, 1716, 1716, 1087,  // 0..?
    2048, 1401, 1405, 1430, 1577, 1294, 1178, 1587, 1540, 604,  604,  1343, 1141, 1767, 1532, 1612,  // @..O
    1235, 1612, 1423, 1300, 1251, 1499, 1401, 2025, 1403, 1251, 1403, 799,  690,  799,  1716, 1024,  // P.._
    1024, 1255, 1300, 1126, 1300, 1260, 721,  1300, 1298, 569,  569,  1186, 569,  1995, 1298, 1253,  // `..o
    1300, 1300, 842,  1067, 803,  1298, 1212, 1675, 1212, 1212, 1075, 1303, 690,  1303, 1716};       // p..~
constexpr double kBoldWidening = 1.1;  // DejaVu Sans Bold is about this much wider

// Code points of UTF-8 text (a malformed byte counts as one character).
std::vector<char32_t> codePoints(std::string_view text) {
  std::vector<char32_t> out;
  for (size_t i = 0; i < text.size();) {
    const auto lead = static_cast<unsigned char>(text[i]);
    const size_t length = lead < 0x80 ? 1 : (lead >> 5) == 6 ? 2 : (lead >> 4) == 14 ? 3 : (lead >> 3) == 30 ? 4 : 1;
    if (length == 1 || i + length > text.size()) {
      out.push_back(lead);
      ++i;
      continue;
    }
    char32_t cp = lead & (0x7F >> length);
    for (size_t k = 1; k < length; ++k) cp = (cp << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3F);
    out.push_back(cp);
    i += length;
  }
  return out;
}

double textWidth(std::string_view text, double size, bool bold = false) {
  double em = 0;
  for (const char32_t cp : codePoints(text))
    em += (cp >= 32 && cp < 127 ? kAdvance[cp - 32] : 1303) / 2048.0;  // others: a digit's width
  return em * size * (bold ? kBoldWidening : 1.0);
}

// OpenImageIO 2.4's render_text draws only ASCII correctly (a multi-byte character comes out as
// its last byte), so the PNG spells the common non-ASCII characters of our labels in ASCII.
std::string asciiFor(std::string_view text) {
  std::string out;
  for (const char32_t cp : codePoints(text)) {
    if (cp < 128) {
      out += static_cast<char>(cp);
      continue;
    }
    switch (cp) {
      case U'×': out += 'x'; break;
      case U'µ': case U'μ': out += 'u'; break;
      case U'–': case U'—': case U'−': case U'⁻': out += '-'; break;
      case U'·': case U'•': out += '.'; break;
      case U'≤': out += "<="; break;
      case U'≥': out += ">="; break;
      case U'≈': out += "~"; break;
      case U'°': out += " deg"; break;
      case U'σ': out += "sigma"; break;
      case U'τ': out += "tau"; break;
      case U'⁰': out += '0'; break;
      case U'¹': out += '1'; break;
      case U'²': out += '2'; break;
      case U'³': out += '3'; break;
      case U'…': out += "..."; break;
      case U'é': case U'è': case U'ê': out += 'e'; break;
      default: out += '?'; break;
    }
  }
  return out;
}

std::string escapeXml(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default:
        // Control characters are not allowed in XML 1.0 (tab and newline are, as spaces).
        out += (static_cast<unsigned char>(ch) < 0x20) ? ' ' : ch;
    }
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Numbers.

std::string stripZeros(std::string text) {
  if (text.find('.') != std::string::npos) {
    while (text.back() == '0') text.pop_back();
    if (text.back() == '.') text.pop_back();
  }
  if (text == "-0") text = "0";
  return text;
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return stripZeros(text);
}

// "1e-4", "2.5e-5", "3e6": for tiny and huge tick values.
std::string exponential(double value) {
  if (value == 0) return "0";
  int exponent = static_cast<int>(std::floor(std::log10(std::fabs(value))));
  double mantissa = value / std::pow(10.0, exponent);
  if (std::fabs(std::round(mantissa * 100) / 100) >= 10) {
    mantissa /= 10;
    ++exponent;
  }
  char text[64];
  std::snprintf(text, sizeof text, "%.3g", mantissa);
  return std::string(text) + "e" + std::to_string(exponent);
}

// SVG coordinates: two decimals are a hundredth of a pixel. Never "nan": a non-finite value
// here would be a bug upstream, and must not make the document invalid.
std::string num(double value) { return std::isfinite(value) ? fixed(value, 2) : "0"; }

// ---------------------------------------------------------------------------------------------
// Validation.

bool isHexColor(const std::string& color) {
  return color.size() == 7 && color[0] == '#' &&
         std::all_of(color.begin() + 1, color.end(), [](unsigned char ch) { return std::isxdigit(ch) != 0; });
}

void requireAxis(const Axis& axis, const char* name) {
  const std::string what = std::string("chart: ") + name + " axis ";
  for (const auto& end : {axis.min, axis.max})
    require(!end || std::isfinite(*end), what + "range must be finite");
  if (axis.log)
    for (const auto& end : {axis.min, axis.max})
      require(!end || *end > 0, what + "is logarithmic: its min and max must be > 0");
  // A span below 1e-9 of the values has no ticks that double can tell apart.
  require(!axis.min || !axis.max || *axis.max - *axis.min > 1e-9 * std::max(std::fabs(*axis.min), std::fabs(*axis.max)),
          what + "min must be less than its max");
}

void validate(const Chart& chart) {
  require(chart.width >= 200 && chart.width <= 8000 && chart.height >= 150 && chart.height <= 8000,
          "chart: size " + std::to_string(chart.width) + "x" + std::to_string(chart.height) +
              " is out of range (200..8000 x 150..8000)");
  requireAxis(chart.x, "x");
  requireAxis(chart.y, "y");
  for (const Series& s : chart.series)
    require(s.color.empty() || isHexColor(s.color),
            "chart: series \"" + s.name + "\" has colour \"" + s.color + "\" (expected #rrggbb)");
}

std::string colorOf(const Chart& chart, size_t seriesIndex) {
  const std::string& given = chart.series[seriesIndex].color;
  return given.empty() ? kPalette[seriesIndex % kPalette.size()] : given;
}

// ---------------------------------------------------------------------------------------------
// Scales and layout.

// Where the text around the plot goes; the public Layout is the part tests need.
struct Geometry {
  Layout layout;
  Target target = Target::Svg;
  bool categorical = false;
  std::string title, subtitle;  // as drawn: shortened to fit a small image
  double titleSize = kTitleSize, subtitleSize = kSubtitleSize;
  double titleX = 0, titleBaseline = 0, subtitleBaseline = 0;
  double xLabelBaseline = 0;
  double yLabelX = 0, yLabelY = 0;  // SVG: the rotated label's centre; PNG: its baseline's start
  int tickRows = 1;                 // x tick label rows (2: long category names alternate)
  double barWidth = 0;              // data units per bar
  std::vector<int> barSlot;         // per series: its index among the bar series, or -1
};

bool drawable(double value, bool log) { return std::isfinite(value) && (!log || value > 0); }

// The smallest step of 1, 2 or 5 × 10^k not below `rough` (so there are at most as many
// ticks as asked for, plus one).
double niceStep(double rough) {
  const double power = std::pow(10.0, std::floor(std::log10(rough)));
  const double f = rough / power * (1 - 1e-9);
  return (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * power;
}

// The next smaller step of the 1, 2, 5 ladder.
double smallerStep(double step) {
  const double power = std::pow(10.0, std::floor(std::log10(step) + 1e-9));
  const double f = step / power;
  return (f > 4.9 ? 2 : f > 1.9 ? 1 : 0.5) * power;
}

void linearTicks(Scale& s, int targetCount) {
  double step = niceStep((s.hi - s.lo) / targetCount);
  const auto tickCount = [&](double d) { return std::floor(s.hi / d + 1e-9) - std::ceil(s.lo / d - 1e-9) + 1; };
  for (int i = 0; i < 64 && tickCount(step) < std::min(3, targetCount); ++i) step = smallerStep(step);  // a lone tick says nothing
  const double first = std::ceil(s.lo / step - 1e-9), last = std::floor(s.hi / step + 1e-9);
  double largest = 0;
  // setRange keeps the span at least 1e-9 of the values, so k stays well inside double's integers.
  for (double k = first; k <= last && s.ticks.size() < 100; ++k) {
    s.ticks.push_back(k == 0 ? 0.0 : k * step);
    largest = std::max(largest, std::fabs(k * step));
  }
  const bool useExponent = step < 1e-3 * (1 - 1e-9) || largest >= 1e6;
  const int decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
  for (const double t : s.ticks) s.labels.push_back(useExponent ? exponential(t) : fixed(t, decimals));
}

std::string logLabel(double value) {
  if (value < 1e-3 || value >= 1e6) return exponential(value);
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

// Powers of ten (every n-th when there are many); with less than two decades also 2 and 5
// times them; with less than two ticks all multiples; failing that, linear ticks.
void logTicks(Scale& s, int targetCount) {
  const double lo = std::log10(s.lo), hi = std::log10(s.hi);
  const int firstPower = static_cast<int>(std::ceil(lo - 1e-9)), lastPower = static_cast<int>(std::floor(hi + 1e-9));
  const int stride = std::max(1, static_cast<int>(std::ceil((lastPower - firstPower + 1) / double(targetCount))));
  const auto inRange = [&](double v) { return v >= s.lo * (1 - 1e-9) && v <= s.hi * (1 + 1e-9); };
  const auto collect = [&](std::initializer_list<int> multiples) {
    std::vector<double> ticks;
    for (int p = static_cast<int>(std::floor(lo)); p <= static_cast<int>(std::ceil(hi)); ++p)
      for (const int m : multiples) {
        const double v = m * std::pow(10.0, p);
        if (inRange(v)) ticks.push_back(v);
      }
    return ticks;
  };
  std::vector<double> ticks;
  for (int p = firstPower; p <= lastPower; ++p)
    if ((p - firstPower) % stride == 0) ticks.push_back(std::pow(10.0, p));
  if (hi - lo < 2) ticks = collect({1, 2, 5});
  if (ticks.size() < 2) ticks = collect({1, 2, 3, 4, 5, 6, 7, 8, 9});
  if (ticks.size() < 2) {
    linearTicks(s, targetCount);
    return;
  }
  std::sort(ticks.begin(), ticks.end());
  s.ticks = ticks;
  for (const double t : s.ticks) s.labels.push_back(logLabel(t));
  // Minor ticks show the scale is logarithmic between sparse labels (not when decades are skipped).
  if (stride == 1)
    for (const double v : collect({2, 3, 4, 5, 6, 7, 8, 9}))
      if (std::none_of(ticks.begin(), ticks.end(), [&](double t) { return std::fabs(t - v) <= 1e-9 * v; }))
        s.minorTicks.push_back(v);
}

// The range shown for `values` (already drawable on this axis), then the axis' own ends.
// stickyZero: bars start at 0, so 0 stays at the axis end instead of being padded past.
void setRange(Scale& s, const Axis& axis, std::vector<double> values, bool stickyZero) {
  if (s.log)
    for (double& v : values) v = std::log10(v);
  double lo = values.empty() ? 0 : *std::min_element(values.begin(), values.end());
  double hi = values.empty() ? 1 : *std::max_element(values.begin(), values.end());
  if (hi - lo <= 1e-9 * std::max(std::fabs(lo), std::fabs(hi))) {  // one value (or as good as one)
    lo = hi = (lo + hi) / 2;
    const double half = s.log ? 0.5 : (lo == 0 ? 1 : std::fabs(lo) * 0.1);
    lo -= half;
    hi += half;
  }
  const double pad = kMargin * (hi - lo);
  const bool zeroAtBottom = stickyZero && !s.log && lo == 0, zeroAtTop = stickyZero && !s.log && hi == 0;
  lo = zeroAtBottom ? 0 : lo - pad;
  hi = zeroAtTop ? 0 : hi + pad;
  if (s.log) {
    lo = std::pow(10.0, lo);
    hi = std::pow(10.0, hi);
  }
  if (axis.min) lo = *axis.min;
  if (axis.max) hi = *axis.max;
  if (!(hi > lo)) hi = s.log ? lo * 10 : lo + std::max(1.0, std::fabs(lo));  // one end given past the data
  s.lo = lo;
  s.hi = hi;
}

int tickTarget(double pixels, double pixelsPerTick) {
  return std::clamp(static_cast<int>(pixels / pixelsPerTick), 3, 10);
}

// Smallest positive gap between distinct x of bar points (1 on a categorical axis).
double barSpacing(const Chart& chart) {
  if (!chart.categories.empty()) return 1;
  std::vector<double> xs;
  for (const Series& s : chart.series)
    if (s.bars)
      for (const Point& p : s.points)
        if (std::isfinite(p.x)) xs.push_back(p.x);
  std::sort(xs.begin(), xs.end());
  double gap = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < xs.size(); ++i)
    if (xs[i] > xs[i - 1]) gap = std::min(gap, xs[i] - xs[i - 1]);
  return std::isfinite(gap) ? gap : 1;
}

// Text that must fit in `room` pixels: smaller down to `minSize`, then cut with an ellipsis.
void fitText(std::string& text, double& size, double minSize, double room, bool bold) {
  const double width = textWidth(text, size, bold);
  if (width <= room) return;
  size = std::max(minSize, size * room / width);
  std::vector<char32_t> cps = codePoints(text);
  while (!cps.empty() && textWidth(text, size, bold) > room) {
    cps.pop_back();
    text.clear();
    for (const char32_t cp : cps) {  // back to UTF-8
      if (cp < 0x80) {
        text += static_cast<char>(cp);
      } else if (cp < 0x800) {
        text += static_cast<char>(0xC0 | (cp >> 6));
        text += static_cast<char>(0x80 | (cp & 0x3F));
      } else if (cp < 0x10000) {
        text += static_cast<char>(0xE0 | (cp >> 12));
        text += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
        text += static_cast<char>(0x80 | (cp & 0x3F));
      } else {
        text += static_cast<char>(0xF0 | (cp >> 18));
        text += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
        text += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
        text += static_cast<char>(0x80 | (cp & 0x3F));
      }
    }
    text += "...";
  }
}

Geometry place(const Chart& chart, Target target, int tickRows) {
  Geometry g;
  g.target = target;
  g.tickRows = tickRows;
  g.categorical = !chart.categories.empty();
  Layout& L = g.layout;
  const double width = chart.width, height = chart.height;
  const bool yLabelOnTop = target == Target::Png && !chart.y.label.empty();

  // Bars: which slot each bar series takes, and how wide a bar is.
  int barCount = 0;
  for (const Series& s : chart.series) g.barSlot.push_back(s.bars ? barCount++ : -1);
  const double spacing = barSpacing(chart);
  g.barWidth = barCount ? kBarGroupShare * spacing / barCount : 0;

  // 1. Top: title, subtitle, and (PNG) the y-axis label, which render_text cannot rotate.
  g.title = chart.title;
  g.subtitle = chart.subtitle;
  fitText(g.title, g.titleSize, 10, width - 2 * kPad, true);
  fitText(g.subtitle, g.subtitleSize, 9, width - 2 * kPad, false);
  double y = kPad;
  if (!g.title.empty()) {
    g.titleBaseline = y + kAscent * g.titleSize;
    y += g.titleSize * kLineHeight;
  }
  if (!g.subtitle.empty()) {
    g.subtitleBaseline = y + kAscent * g.subtitleSize;
    y += g.subtitleSize * kLineHeight;
  }
  if (!chart.title.empty() || !chart.subtitle.empty()) y += 8;
  if (yLabelOnTop) {
    g.yLabelY = y + kAscent * kLabelSize;
    y += kLabelSize * kLineHeight + 2;
  }
  L.top = std::round(std::max(y, kPad + kTickSize * 0.5));  // half the top tick label sticks out

  // 2. Bottom: x-axis label, then the tick label rows.
  double b = height - kPad;
  if (!chart.x.label.empty()) {
    g.xLabelBaseline = b - kDescent * kLabelSize;
    b -= kLabelSize * kLineHeight + 3;
  }
  b -= tickRows * kTickSize * kLineHeight + kTickLength + kTickGap;
  L.bottom = std::round(b);

  // 3. The y scale (its tick labels decide the left margin).
  L.y.log = chart.y.log;
  std::vector<double> ys;
  bool anyBars = false;
  for (const Series& s : chart.series) {
    anyBars = anyBars || s.bars;
    for (const Point& p : s.points)
      if (drawable(p.y, L.y.log) && (g.categorical || drawable(p.x, chart.x.log))) ys.push_back(p.y);
  }
  for (const Guide& guide : chart.guides)
    if (!guide.vertical && drawable(guide.value, L.y.log)) ys.push_back(guide.value);
  if (anyBars && !L.y.log) ys.push_back(0);
  setRange(L.y, chart.y, ys, anyBars);
  (L.y.log ? logTicks : linearTicks)(L.y, tickTarget(L.bottom - L.top, 55));
  L.y.pixelLo = L.bottom;
  L.y.pixelHi = L.top;

  double widest = 0;
  for (const std::string& label : L.y.labels) widest = std::max(widest, textWidth(label, kTickSize));
  double x = kPad;
  if (target == Target::Svg && !chart.y.label.empty()) {
    g.yLabelX = x + kAscent * kLabelSize;
    x += kLabelSize * kLineHeight + 4;
  }
  L.left = std::round(x + widest + kTickGap + kTickLength);
  g.yLabelY = yLabelOnTop ? g.yLabelY : (L.top + L.bottom) / 2;
  if (yLabelOnTop) g.yLabelX = kPad;

  // 4. The x scale; the right margin grows when the last tick label would stick out.
  L.x.log = chart.x.log && !g.categorical;
  std::vector<double> xs;
  for (const Series& s : chart.series)
    for (const Point& p : s.points)
      if (drawable(p.x, L.x.log) && drawable(p.y, L.y.log)) {
        xs.push_back(p.x);
        if (s.bars && !L.x.log) {  // the whole bar group must fit
          xs.push_back(p.x - kBarGroupShare * spacing / 2);
          xs.push_back(p.x + kBarGroupShare * spacing / 2);
        }
      }
  for (const Guide& guide : chart.guides)
    if (guide.vertical && drawable(guide.value, L.x.log)) xs.push_back(guide.value);
  L.right = width - kPad;
  for (int pass = 0; pass < 2; ++pass) {
    L.x.ticks.clear();
    L.x.labels.clear();
    L.x.minorTicks.clear();
    L.x.pixelLo = L.left;
    L.x.pixelHi = L.right;
    if (g.categorical) {
      const double n = static_cast<double>(chart.categories.size());
      L.x.lo = chart.x.min.value_or(-0.5);
      L.x.hi = chart.x.max.value_or(n - 0.5);
      if (!(L.x.hi > L.x.lo)) L.x.hi = L.x.lo + 1;
      for (size_t i = 0; i < chart.categories.size(); ++i) {
        L.x.ticks.push_back(static_cast<double>(i));
        L.x.labels.push_back(chart.categories[i]);
      }
      break;  // category labels are centred well inside the plot
    }
    setRange(L.x, chart.x, xs, false);
    (L.x.log ? logTicks : linearTicks)(L.x, tickTarget(L.right - L.left, 90));
    if (pass == 1 || L.x.ticks.empty()) break;
    const double lastEnd = *L.x.toPixel(L.x.ticks.back()) + textWidth(L.x.labels.back(), kTickSize) / 2;
    if (lastEnd <= width - 4) break;
    L.right = std::round(L.right - (lastEnd - (width - 4)));
  }

  // 5. Text centred over the plot (kept inside the image).
  const double titleWidth = std::max(textWidth(g.title, g.titleSize, true), textWidth(g.subtitle, g.subtitleSize));
  g.titleX = std::clamp((L.left + L.right) / 2, kPad + titleWidth / 2, std::max(kPad + titleWidth / 2, width - kPad - titleWidth / 2));
  return g;
}

Geometry geometryOf(const Chart& chart, Target target) {
  validate(chart);
  Geometry g = place(chart, target, 1);
  if (!g.categorical) return g;
  // Category names wider than their slot alternate between two rows.
  const double slot = (g.layout.right - g.layout.left) / (g.layout.x.hi - g.layout.x.lo);
  for (const std::string& name : chart.categories)
    if (textWidth(name, kTickSize) > slot - 6) return place(chart, target, 2);
  return g;
}

// ---------------------------------------------------------------------------------------------
// What a renderer must draw: one Canvas per output format; draw() below is written once.

struct Vec {
  double x = 0, y = 0;
};

enum class Anchor { Start, Middle, End };

struct Stroke {
  std::string color;
  double width = 1;
  const double* dash = nullptr;  // {on, off} lengths, or solid
  bool round = false;            // round caps and joins (else butt)
};

struct TextStyle {
  double size = kTickSize;
  std::string color = kTextColor;
  Anchor anchor = Anchor::Start;
  bool bold = false;
  bool vertical = false;  // rotated 90° counter-clockwise about its anchor (SVG only)
};

class Canvas {
 public:
  virtual ~Canvas() = default;
  // A polyline; `clipped` keeps it inside the plot area.
  virtual void polyline(const std::vector<Vec>& points, const Stroke& stroke, bool clipped) = 0;
  // An axis-aligned rectangle from `a` to `b`; an empty fill or stroke colour draws none.
  virtual void rect(Vec a, Vec b, const std::string& fill, double fillOpacity, const std::string& stroke,
                    double strokeWidth, const std::string& tooltip) = 0;
  virtual void marker(Vec centre, Marker marker, const std::string& color, bool hollow,
                      const std::string& tooltip) = 0;
  // `at`: the anchor point on the text's baseline.
  virtual void text(Vec at, const std::string& text, const TextStyle& style) = 0;
};

// Axis-aligned lines one pixel wide look sharp only through pixel centres.
double crisp(double v) { return std::floor(v) + 0.5; }

struct Box {
  double x0, y0, x1, y1;
  bool contains(Vec p, double margin) const {
    return p.x >= x0 - margin && p.x <= x1 + margin && p.y >= y0 - margin && p.y <= y1 + margin;
  }
  bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

// What the legend should not hide: marker centres, points along lines, bars, guide labels.
struct Obstacles {
  std::vector<Vec> points;
  std::vector<Box> boxes;
  int cost(const Box& b) const {
    int n = 0;
    for (const Vec& p : points) n += b.contains(p, kMarkerRadius) ? 1 : 0;
    for (const Box& o : boxes) n += b.overlaps(o) ? 5 : 0;
    return n;
  }
};

std::vector<Vec> sampleSegment(Vec a, Vec b, double every) {
  const double length = std::hypot(b.x - a.x, b.y - a.y);
  const int n = std::min(10000, static_cast<int>(length / every) + 1);
  std::vector<Vec> out;
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
  }
  return out;
}

void drawLegend(const Chart& chart, const Geometry& g, const Obstacles& obstacles, Canvas& canvas) {
  std::vector<size_t> entries;
  double widest = 0;
  for (size_t i = 0; i < chart.series.size(); ++i)
    if (!chart.series[i].name.empty()) {
      entries.push_back(i);
      widest = std::max(widest, textWidth(chart.series[i].name, kLegendSize));
    }
  if (entries.empty()) return;
  const Layout& L = g.layout;
  constexpr double kInset = 10, kBoxPad = 7, kSample = 30, kSampleGap = 7, kRow = kLegendSize * 1.5;
  const double w = kBoxPad + kSample + kSampleGap + widest + kBoxPad;
  const double h = 2 * (kBoxPad - 2) + kRow * static_cast<double>(entries.size());
  // Top-right unless another place hides less (ties keep the earlier place): the four corners,
  // then each moved away from its edge by a guide label's height, then the middles of the
  // top and bottom edges.
  const double xs[3] = {L.right - kInset - w, L.left + kInset, (L.left + L.right - w) / 2};
  const double ys[2] = {L.top + kInset, L.bottom - kInset - h};
  const double shift = kGuideSize * kLineHeight + 4;
  std::vector<Vec> places;
  for (const double dy : {0.0, shift})
    for (int corner = 0; corner < 4; ++corner) places.push_back({xs[corner % 2], corner < 2 ? ys[0] + dy : ys[1] - dy});
  places.push_back({xs[2], ys[0]});
  places.push_back({xs[2], ys[1]});
  Vec at = places[0];
  int best = std::numeric_limits<int>::max();
  for (const Vec& c : places) {
    const int cost = obstacles.cost({c.x, c.y, c.x + w, c.y + h});
    if (cost < best) {
      best = cost;
      at = c;
    }
  }
  at = {std::round(at.x), std::round(at.y)};
  canvas.rect({at.x + 0.5, at.y + 0.5}, {at.x + std::round(w) - 0.5, at.y + std::round(h) - 0.5}, kBackground,
              kLegendOpacity, kLegendBorder, 1, "");
  for (size_t row = 0; row < entries.size(); ++row) {
    const Series& s = chart.series[entries[row]];
    const std::string color = colorOf(chart, entries[row]);
    const double yc = at.y + kBoxPad - 2 + kRow * (static_cast<double>(row) + 0.5);
    const double x0 = at.x + kBoxPad;
    if (s.bars) {
      canvas.rect({x0 + 4, yc - 5}, {x0 + kSample - 4, yc + 5}, color, 1, "", 0, "");
    } else {
      if (s.line) canvas.polyline({{x0, yc}, {x0 + kSample, yc}}, {color, kLineWidth, s.dashed ? kSeriesDash : nullptr, !s.dashed}, false);
      if (s.marker != Marker::None) canvas.marker({x0 + kSample / 2, yc}, s.marker, color, s.hollow, "");
    }
    TextStyle style{kLegendSize, kTextColor};
    canvas.text({x0 + kSample + kSampleGap, yc + kMidCap * kLegendSize}, s.name, style);
  }
}

void draw(const Chart& chart, const Geometry& g, Canvas& canvas) {
  const Layout& L = g.layout;
  const Stroke grid{kGridColor, 1};
  const Stroke frame{kFrameColor, 1};
  Obstacles obstacles;

  // 1. Grid (under everything), at the ticks inside the plot; none across categories.
  for (const double t : L.y.ticks) {
    const double py = crisp(*L.y.toPixel(t));
    if (py > L.top && py < L.bottom) canvas.polyline({{L.left, py}, {L.right, py}}, grid, false);
  }
  if (!g.categorical)
    for (const double t : L.x.ticks) {
      const double px = crisp(*L.x.toPixel(t));
      if (px > L.left && px < L.right) canvas.polyline({{px, L.top}, {px, L.bottom}}, grid, false);
    }

  // 2. Guides: dashed grey lines across the plot.
  struct GuideLabel {
    Vec at;
    Anchor anchor;
    std::string text;
  };
  std::vector<GuideLabel> guideLabels;
  for (const Guide& guide : chart.guides) {
    const Scale& scale = guide.vertical ? L.x : L.y;
    const std::optional<double> p = scale.toPixel(guide.value);
    if (!p || *p < std::min(scale.pixelLo, scale.pixelHi) || *p > std::max(scale.pixelLo, scale.pixelHi)) continue;
    const Stroke dashed{kGuideColor, 1.2, kGuideDash};
    const double labelWidth = textWidth(guide.label, kGuideSize);
    if (guide.vertical) {
      canvas.polyline({{*p, L.top}, {*p, L.bottom}}, dashed, true);
      const bool leftOfLine = *p + 4 + labelWidth > L.right - 2;  // no room on the right
      guideLabels.push_back({{leftOfLine ? *p - 4 : *p + 4, L.top + 4 + kAscent * kGuideSize},
                             leftOfLine ? Anchor::End : Anchor::Start, guide.label});
    } else {
      canvas.polyline({{L.left, *p}, {L.right, *p}}, dashed, true);
      const bool below = *p - 4 - kGuideSize < L.top;  // no room above
      guideLabels.push_back({{L.right - 5, below ? *p + 4 + kAscent * kGuideSize : *p - 4}, Anchor::End, guide.label});
    }
    const GuideLabel& last = guideLabels.back();
    const double x0 = last.anchor == Anchor::End ? last.at.x - labelWidth : last.at.x;
    if (!guide.label.empty()) obstacles.boxes.push_back({x0, last.at.y - kGuideSize, x0 + labelWidth, last.at.y + 2});
  }

  // 3. Bars, from 0 (or the bottom of a log axis), clipped to the plot.
  const double base = L.y.log ? L.bottom : std::clamp(*L.y.toPixel(0), L.top, L.bottom);
  const int barCount = g.barSlot.empty() ? 0 : *std::max_element(g.barSlot.begin(), g.barSlot.end()) + 1;
  for (size_t i = 0; i < chart.series.size(); ++i) {
    const Series& s = chart.series[i];
    if (!s.bars) continue;
    const double offset = (g.barSlot[i] - (barCount - 1) / 2.0) * g.barWidth;
    for (const Point& p : s.points) {
      const auto x0 = L.x.toPixel(p.x + offset - g.barWidth / 2), x1 = L.x.toPixel(p.x + offset + g.barWidth / 2);
      const auto top = L.y.toPixel(p.y);
      if (!x0 || !x1 || !top) continue;
      // A hair of white between neighbouring bars, as long as the bar stays visible.
      const double gap = std::min(0.5, (*x1 - *x0) / 4);
      const Box box{std::clamp(std::min(*x0, *x1) + gap, L.left, L.right), std::clamp(std::min(base, *top), L.top, L.bottom),
                    std::clamp(std::max(*x0, *x1) - gap, L.left, L.right), std::clamp(std::max(base, *top), L.top, L.bottom)};
      if (box.x1 <= box.x0) continue;
      canvas.rect({box.x0, box.y0}, {box.x1, box.y1}, colorOf(chart, i), 1, "", 0, p.label);
      obstacles.boxes.push_back(box);
    }
  }

  // 4. Lines and markers, series by series (later series on top, as in matplotlib).
  const Box plot{L.left, L.top, L.right, L.bottom};
  for (size_t i = 0; i < chart.series.size(); ++i) {
    const Series& s = chart.series[i];
    if (s.bars) continue;
    const std::string color = colorOf(chart, i);
    std::vector<std::optional<Vec>> pixels;
    for (const Point& p : s.points) {
      const auto px = L.toPixel(p.x, p.y);
      pixels.push_back(px ? std::optional<Vec>(Vec{(*px)[0], (*px)[1]}) : std::nullopt);
    }
    if (s.line) {
      // A point that cannot be drawn (log axis) breaks the line, as in matplotlib.
      std::vector<Vec> run;
      const auto flush = [&] {
        if (run.size() >= 2) {
          canvas.polyline(run, {color, kLineWidth, s.dashed ? kSeriesDash : nullptr, !s.dashed}, true);
          for (size_t k = 1; k < run.size(); ++k)
            for (const Vec& v : sampleSegment(run[k - 1], run[k], 4))
              if (plot.contains(v, 0)) obstacles.points.push_back(v);
        }
        run.clear();
      };
      for (const auto& px : pixels) {
        if (px) run.push_back(*px);
        else flush();
      }
      flush();
    }
    for (size_t k = 0; k < pixels.size(); ++k) {
      if (!pixels[k] || !plot.contains(*pixels[k], 0.5)) continue;
      if (s.marker == Marker::None && s.points[k].label.empty()) continue;
      canvas.marker(*pixels[k], s.marker, color, s.hollow, s.points[k].label);
      obstacles.points.push_back(*pixels[k]);
    }
  }

  // 5. Frame, ticks and tick labels.
  canvas.rect({L.left + 0.5, L.top + 0.5}, {L.right - 0.5, L.bottom - 0.5}, "", 0, kFrameColor, 1, "");
  for (size_t k = 0; k < L.y.ticks.size(); ++k) {
    const double py = crisp(*L.y.toPixel(L.y.ticks[k]));
    if (py < L.top - 0.5 || py > L.bottom + 0.5) continue;
    canvas.polyline({{L.left - kTickLength, py}, {L.left, py}}, frame, false);
    canvas.text({L.left - kTickLength - kTickGap, py + kMidCap * kTickSize}, L.y.labels[k],
                {kTickSize, kTickTextColor, Anchor::End});
  }
  for (const double t : L.y.minorTicks) {
    const double py = crisp(*L.y.toPixel(t));
    canvas.polyline({{L.left - kMinorTickLength, py}, {L.left, py}}, frame, false);
  }
  for (const double t : L.x.minorTicks) {
    const double px = crisp(*L.x.toPixel(t));
    canvas.polyline({{px, L.bottom}, {px, L.bottom + kMinorTickLength}}, frame, false);
  }
  for (size_t k = 0; k < L.x.ticks.size(); ++k) {
    const double px = crisp(*L.x.toPixel(L.x.ticks[k]));
    if (px < L.left - 0.5 || px > L.right + 0.5) continue;
    canvas.polyline({{px, L.bottom}, {px, L.bottom + kTickLength}}, frame, false);
    const double row = g.tickRows > 1 ? static_cast<double>(k % 2) : 0;
    canvas.text({px, L.bottom + kTickLength + kTickGap + kAscent * kTickSize + row * kTickSize * kLineHeight},
                L.x.labels[k], {kTickSize, kTickTextColor, Anchor::Middle});
  }

  // 6. Guide labels and the legend, over the data.
  for (const GuideLabel& label : guideLabels) {
    if (label.text.empty()) continue;
    // On a light backing, so the label stays readable over bars and lines.
    const double w = textWidth(label.text, kGuideSize), x0 = label.anchor == Anchor::End ? label.at.x - w : label.at.x;
    canvas.rect({x0 - 2, label.at.y - kAscent * kGuideSize - 1}, {x0 + w + 2, label.at.y + kDescent * kGuideSize},
                kBackground, kLegendOpacity, "", 0, "");
    canvas.text(label.at, label.text, {kGuideSize, kGuideColor, label.anchor});
  }
  drawLegend(chart, g, obstacles, canvas);

  // 7. Title, subtitle, axis labels.
  if (!g.title.empty()) canvas.text({g.titleX, g.titleBaseline}, g.title, {g.titleSize, kTextColor, Anchor::Middle, true});
  if (!g.subtitle.empty())
    canvas.text({g.titleX, g.subtitleBaseline}, g.subtitle, {g.subtitleSize, kSubtitleColor, Anchor::Middle});
  if (!chart.x.label.empty())
    canvas.text({(L.left + L.right) / 2, g.xLabelBaseline}, chart.x.label, {kLabelSize, kTextColor, Anchor::Middle});
  if (!chart.y.label.empty()) {
    if (g.target == Target::Svg)
      canvas.text({g.yLabelX, g.yLabelY}, chart.y.label, {kLabelSize, kTextColor, Anchor::Middle, false, true});
    else
      canvas.text({g.yLabelX, g.yLabelY}, chart.y.label, {kLabelSize, kTextColor, Anchor::Start});
  }
}

// ---------------------------------------------------------------------------------------------
// Marker shapes, shared by both canvases: convex outlines around the marker's centre.

// A regular polygon's radius grown so that its edges move out by `offset`.
double grownRadius(double radius, int sides, double offset) {
  return radius + offset / std::cos(std::numbers::pi / sides);
}

// Triangle (pointing up, centred on its centroid), square and diamond outlines; `offset`
// moves the edges out (or in, when negative) for outlines of hollow markers.
std::vector<Vec> markerPolygon(Marker marker, Vec c, double offset) {
  std::vector<Vec> out;
  const auto regular = [&](int sides, double radius, double startDegrees) {
    const double r = grownRadius(radius, sides, offset);
    for (int k = 0; k < sides; ++k) {
      const double a = (startDegrees + 360.0 * k / sides) * std::numbers::pi / 180;
      out.push_back({c.x + r * std::cos(a), c.y + r * std::sin(a)});
    }
  };
  switch (marker) {
    case Marker::Triangle: regular(3, kMarkerRadius * 1.3, -90); break;
    case Marker::Square: regular(4, kMarkerRadius * 1.2, 45); break;
    case Marker::Diamond: regular(4, kMarkerRadius * 1.25, -90); break;
    default: break;
  }
  return out;
}

// The two strokes of a cross (×).
std::array<std::array<Vec, 2>, 2> crossStrokes(Vec c) {
  const double a = kMarkerRadius * 0.85;
  std::array<std::array<Vec, 2>, 2> strokes;
  strokes[0] = {Vec{c.x - a, c.y - a}, Vec{c.x + a, c.y + a}};
  strokes[1] = {Vec{c.x - a, c.y + a}, Vec{c.x + a, c.y - a}};
  return strokes;
}

// ---------------------------------------------------------------------------------------------
// SVG.

class SvgCanvas : public Canvas {
 public:
  explicit SvgCanvas(std::string& out) : out_(out) {}

  void polyline(const std::vector<Vec>& points, const Stroke& stroke, bool clipped) override {
    out_ += "<polyline points=\"";
    for (size_t i = 0; i < points.size(); ++i) {  // appended piece by piece: GCC 12 warns falsely on " " + string
      if (i) out_ += ' ';
      out_ += num(points[i].x);
      out_ += ',';
      out_ += num(points[i].y);
    }
    out_ += "\" fill=\"none\" stroke=\"" + stroke.color + "\" stroke-width=\"" + num(stroke.width) + "\"";
    out_ += stroke.round ? " stroke-linecap=\"round\" stroke-linejoin=\"round\"" : " stroke-linecap=\"butt\"";
    if (stroke.dash) out_ += " stroke-dasharray=\"" + num(stroke.dash[0]) + " " + num(stroke.dash[1]) + "\"";
    if (clipped) out_ += " clip-path=\"url(#mrr-plot-area)\"";
    out_ += "/>\n";
  }

  void rect(Vec a, Vec b, const std::string& fill, double fillOpacity, const std::string& stroke, double strokeWidth,
            const std::string& tooltip) override {
    std::string element = "<rect x=\"" + num(std::min(a.x, b.x)) + "\" y=\"" + num(std::min(a.y, b.y)) +
                          "\" width=\"" + num(std::fabs(b.x - a.x)) + "\" height=\"" + num(std::fabs(b.y - a.y)) + "\"";
    element += " fill=\"" + (fill.empty() ? std::string("none") : fill) + "\"";
    if (!fill.empty() && fillOpacity < 1) element += " fill-opacity=\"" + num(fillOpacity) + "\"";
    if (!stroke.empty()) element += " stroke=\"" + stroke + "\" stroke-width=\"" + num(strokeWidth) + "\"";
    close(element, tooltip);
  }

  void marker(Vec c, Marker marker, const std::string& color, bool hollow, const std::string& tooltip) override {
    const std::string paint = hollow ? " fill=\"" + std::string(kBackground) + "\" stroke=\"" + color +
                                           "\" stroke-width=\"" + num(kHollowStroke) + "\""
                                     : " fill=\"" + color + "\"";
    switch (marker) {
      case Marker::Circle:
        close("<circle cx=\"" + num(c.x) + "\" cy=\"" + num(c.y) + "\" r=\"" + num(kMarkerRadius) + "\"" + paint, tooltip);
        return;
      case Marker::Cross: {
        const auto strokes = crossStrokes(c);
        std::string d;
        for (const auto& s : strokes)
          d += "M" + num(s[0].x) + " " + num(s[0].y) + "L" + num(s[1].x) + " " + num(s[1].y);
        close("<path d=\"" + d + "\" stroke=\"" + color + "\" stroke-width=\"" + num(kCrossStroke) + "\" fill=\"none\"",
              tooltip);
        return;
      }
      case Marker::None:  // only here for a tooltip: an invisible hover target
        close("<circle cx=\"" + num(c.x) + "\" cy=\"" + num(c.y) + "\" r=\"" + num(kMarkerRadius) +
                  "\" fill=\"#ffffff\" fill-opacity=\"0\"",
              tooltip);
        return;
      default: {
        std::string points;
        for (const Vec& v : markerPolygon(marker, c, 0)) {
          if (!points.empty()) points += ' ';
          points += num(v.x);
          points += ',';
          points += num(v.y);
        }
        close("<polygon points=\"" + points + "\"" + paint, tooltip);
        return;
      }
    }
  }

  void text(Vec at, const std::string& text, const TextStyle& style) override {
    out_ += "<text x=\"" + num(at.x) + "\" y=\"" + num(at.y) + "\" font-size=\"" + num(style.size) + "\" fill=\"" +
            style.color + "\"";
    if (style.anchor != Anchor::Start) out_ += style.anchor == Anchor::Middle ? " text-anchor=\"middle\"" : " text-anchor=\"end\"";
    if (style.bold) out_ += " font-weight=\"bold\"";
    if (style.vertical) out_ += " transform=\"rotate(-90 " + num(at.x) + " " + num(at.y) + ")\"";
    out_ += ">" + escapeXml(text) + "</text>\n";
  }

 private:
  // Ends an element, with a <title> child (a hover tooltip in browsers) when there is a tooltip.
  void close(const std::string& element, const std::string& tooltip) {
    if (tooltip.empty()) {
      out_ += element + "/>\n";
      return;
    }
    const std::string name = element.substr(1, element.find(' ') - 1);
    out_ += element + "><title>" + escapeXml(tooltip) + "</title></" + name + ">\n";
  }

  std::string& out_;
};

// ---------------------------------------------------------------------------------------------
// PNG: drawn at kSupersample× into a premultiplied RGBA ImageBuf (OIIO's render_* do "over"
// with the colour's alpha), shapes filled row by row with render_box, then downsampled with a
// box filter: each output pixel is the mean of its kSupersample² samples (antialiasing).

using Rgba = std::array<float, 4>;

Rgba parseColor(const std::string& hex, double opacity = 1) {
  const auto channel = [&](size_t at) { return static_cast<float>(std::stoi(hex.substr(at, 2), nullptr, 16)) / 255.0f; };
  const auto a = static_cast<float>(opacity);
  return {channel(1) * a, channel(3) * a, channel(5) * a, a};
}

// The x-interval a convex shape covers on a row (pixel-centre line y), if any.
struct Span {
  double x0 = 0, x1 = -1;
  bool empty() const { return x1 < x0; }
  Span join(const Span& o) const { return empty() ? o : o.empty() ? *this : Span{std::min(x0, o.x0), std::max(x1, o.x1)}; }
};

Span discSpan(Vec c, double r, double y) {
  const double dy = y - c.y;
  if (std::fabs(dy) > r) return {};
  const double half = std::sqrt(r * r - dy * dy);
  return {c.x - half, c.x + half};
}

Span polygonSpan(const std::vector<Vec>& poly, double y) {
  Span s{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  int hits = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec p = poly[i], q = poly[(i + 1) % poly.size()];
    if ((p.y <= y && y < q.y) || (q.y <= y && y < p.y)) {
      const double x = p.x + (y - p.y) * (q.x - p.x) / (q.y - p.y);
      s = {std::min(s.x0, x), std::max(s.x1, x)};
      ++hits;
    }
  }
  return hits >= 2 ? s : Span{};
}

// Liang–Barsky: the part of segment a-b inside the box, if any.
bool clipSegment(Vec& a, Vec& b, const Box& box) {
  double t0 = 0, t1 = 1;
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double p[4] = {-dx, dx, -dy, dy}, q[4] = {a.x - box.x0, box.x1 - a.x, a.y - box.y0, box.y1 - a.y};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0) {
      if (q[k] < 0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0) t0 = std::max(t0, t);
    else t1 = std::min(t1, t);
  }
  if (t0 > t1) return false;
  b = {a.x + t1 * dx, a.y + t1 * dy};
  a = {a.x + t0 * dx, a.y + t0 * dy};
  return true;
}

class PngCanvas : public Canvas {
 public:
  PngCanvas(const Layout& layout, int width, int height, const std::string& path)
      : path_(path),
        buf_(OIIO::ImageSpec(width * kSupersample, height * kSupersample, 4, OIIO::TypeDesc::FLOAT)),
        plot_{layout.left * kSupersample, layout.top * kSupersample, layout.right * kSupersample,
              layout.bottom * kSupersample} {
    for (const char* font : {kFontFile, kBoldFontFile})
      require(fs::exists(font), "cannot draw " + path + ": font " + font + " is missing (install the package " +
                                    kFontPackage + ")");
    buf_.specmod().alpha_channel = 3;
    OIIO::ImageBufAlgo::fill(buf_, background_);
  }

  void polyline(const std::vector<Vec>& points, const Stroke& stroke, bool clipped) override {
    const Rgba color = parseColor(stroke.color);
    const double half = stroke.width * kSupersample / 2;
    const auto segment = [&](Vec a, Vec b, bool caps) {
      a = scaled(a);
      b = scaled(b);
      if (clipped && !clipSegment(a, b, {plot_.x0 - half, plot_.y0 - half, plot_.x1 + half, plot_.y1 + half})) return;
      capsule(a, b, half, caps, color, clipped);
    };
    if (!stroke.dash) {
      for (size_t i = 1; i < points.size(); ++i) segment(points[i - 1], points[i], stroke.round);
      return;
    }
    // Dashes run on along the polyline, across its corners.
    const double on = stroke.dash[0], period = stroke.dash[0] + stroke.dash[1];
    double phase = 0;  // distance along the pattern where this segment starts
    for (size_t i = 1; i < points.size(); ++i) {
      const Vec a = points[i - 1], b = points[i];
      const double length = std::hypot(b.x - a.x, b.y - a.y);
      const int maxDashes = 100000;  // a segment far outside the plot must not take forever
      double t = 0;
      for (int n = 0; t < length && n < maxDashes; ++n) {
        const double inPeriod = std::fmod(phase + t, period);
        const double run = inPeriod < on ? on - inPeriod : period - inPeriod;
        const double end = std::min(length, t + run);
        if (inPeriod < on) {
          const auto at = [&](double d) { return Vec{a.x + (b.x - a.x) * d / length, a.y + (b.y - a.y) * d / length}; };
          segment(at(t), at(end), false);
        }
        t = end;
      }
      phase = std::fmod(phase + length, period);
    }
  }

  void rect(Vec a, Vec b, const std::string& fill, double fillOpacity, const std::string& stroke, double strokeWidth,
            const std::string&) override {
    const Vec p = scaled({std::min(a.x, b.x), std::min(a.y, b.y)}), q = scaled({std::max(a.x, b.x), std::max(a.y, b.y)});
    if (!fill.empty()) {
      const int x0 = firstPixel(p.x), x1 = lastPixel(q.x), y0 = firstPixel(p.y), y1 = lastPixel(q.y);
      if (x0 <= x1 && y0 <= y1) box(x0, y0, x1, y1, parseColor(fill, fillOpacity), true);
    }
    if (!stroke.empty()) {
      // A stroke of width w is w·kSupersample nested one-pixel outlines centred on the edge.
      const int n = std::max(1, static_cast<int>(std::lround(strokeWidth * kSupersample)));
      const Rgba color = parseColor(stroke);
      const int x0 = static_cast<int>(std::lround(p.x - n / 2.0)), y0 = static_cast<int>(std::lround(p.y - n / 2.0));
      const int x1 = static_cast<int>(std::lround(q.x + n / 2.0)) - 1, y1 = static_cast<int>(std::lround(q.y + n / 2.0)) - 1;
      for (int k = 0; k < n && x0 + k <= x1 - k && y0 + k <= y1 - k; ++k) box(x0 + k, y0 + k, x1 - k, y1 - k, color, false);
    }
  }

  void marker(Vec c, Marker marker, const std::string& color, bool hollow, const std::string&) override {
    const Rgba rgba = parseColor(color);
    const double s = kSupersample, ring = kHollowStroke / 2;
    const Vec centre = scaled(c);
    switch (marker) {
      case Marker::None: return;
      case Marker::Circle: {
        const double outer = (kMarkerRadius + (hollow ? ring : 0)) * s, inner = (kMarkerRadius - ring) * s;
        fillRows(centre.y - outer, centre.y + outer, rgba, [&](double y) { return discSpan(centre, outer, y); },
                 [&](double y) { return hollow ? discSpan(centre, inner, y) : Span{}; });
        if (hollow)
          fillRows(centre.y - inner, centre.y + inner, background_, [&](double y) { return discSpan(centre, inner, y); },
                   [](double) { return Span{}; });
        return;
      }
      case Marker::Cross:
        for (const auto& stroke : crossStrokes(c)) capsule(scaled(stroke[0]), scaled(stroke[1]), kCrossStroke * s / 2, false, rgba, false);
        return;
      default: {
        const auto scaleAll = [&](std::vector<Vec> poly) {
          for (Vec& v : poly) v = scaled(v);
          return poly;
        };
        const std::vector<Vec> outer = scaleAll(markerPolygon(marker, c, hollow ? ring : 0));
        const std::vector<Vec> inner = scaleAll(markerPolygon(marker, c, -ring));
        double y0 = outer[0].y, y1 = outer[0].y;
        for (const Vec& v : outer) {
          y0 = std::min(y0, v.y);
          y1 = std::max(y1, v.y);
        }
        fillRows(y0, y1, rgba, [&](double y) { return polygonSpan(outer, y); },
                 [&](double y) { return hollow ? polygonSpan(inner, y) : Span{}; });
        if (hollow)
          fillRows(y0, y1, background_, [&](double y) { return polygonSpan(inner, y); }, [](double) { return Span{}; });
        return;
      }
    }
  }

  void text(Vec at, const std::string& text, const TextStyle& style) override {
    if (text.empty()) return;
    const Vec p = scaled(at);
    const Rgba color = parseColor(style.color);
    const auto align = style.anchor == Anchor::Start    ? OIIO::ImageBufAlgo::TextAlignX::Left
                       : style.anchor == Anchor::Middle ? OIIO::ImageBufAlgo::TextAlignX::Center
                                                        : OIIO::ImageBufAlgo::TextAlignX::Right;
    if (!OIIO::ImageBufAlgo::render_text(buf_, static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)),
                                         asciiFor(text), static_cast<int>(std::lround(style.size * kSupersample)),
                                         style.bold ? kBoldFontFile : kFontFile, color, align,
                                         OIIO::ImageBufAlgo::TextAlignY::Baseline, 0, {}, 1))
      throw MrrError("cannot draw " + path_ + ": " + buf_.geterror());
  }

  // The opaque RGB image at the output size.
  ImageF finish(int width, int height) {
    const OIIO::ImageBuf rgb = OIIO::ImageBufAlgo::channels(buf_, 3, {0, 1, 2});
    const OIIO::ImageBuf small =
        OIIO::ImageBufAlgo::resize(rgb, "box", 1.0f, OIIO::ROI(0, width, 0, height, 0, 1, 0, 3));
    ImageF image(width, height, 3);
    if (small.has_error() || !small.get_pixels(OIIO::ROI(0, width, 0, height, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, image.data.data()))
      throw MrrError("cannot draw " + path_ + ": " + small.geterror());
    return image;
  }

 private:
  static Vec scaled(Vec v) { return {v.x * kSupersample, v.y * kSupersample}; }
  // Pixels whose centres lie in [a, b].
  static int firstPixel(double a) { return static_cast<int>(std::ceil(a - 0.5)); }
  static int lastPixel(double b) { return static_cast<int>(std::floor(b - 0.5)); }

  void box(int x0, int y0, int x1, int y1, const Rgba& color, bool fill) {
    OIIO::ImageBufAlgo::render_box(buf_, x0, y0, x1, y1, color, fill, {}, 1);
  }

  // Fills, row by row, what `outer` covers and `inner` does not (a ring for hollow markers).
  template <class Outer, class Inner>
  void fillRows(double y0, double y1, const Rgba& color, Outer outer, Inner inner, const Box* clip = nullptr) {
    const double height = buf_.spec().height, width = buf_.spec().width;
    const Box bounds = clip ? *clip : Box{0, 0, width, height};
    const int rowFirst = std::max(firstPixel(std::max(y0, bounds.y0)), 0);
    const int rowLast = std::min(lastPixel(std::min(y1, bounds.y1)), static_cast<int>(height) - 1);
    const int colFirst = std::max(firstPixel(bounds.x0), 0), colLast = std::min(lastPixel(bounds.x1), static_cast<int>(width) - 1);
    for (int j = rowFirst; j <= rowLast; ++j) {
      const double y = j + 0.5;
      const Span out = outer(y);
      if (out.empty()) continue;
      const int a = std::max(firstPixel(out.x0), colFirst), b = std::min(lastPixel(out.x1), colLast);
      const Span in = inner(y);
      if (in.empty()) {
        if (a <= b) box(a, j, b, j, color, true);
        continue;
      }
      const int holeFirst = firstPixel(in.x0), holeLast = lastPixel(in.x1);
      if (a <= std::min(b, holeFirst - 1)) box(a, j, std::min(b, holeFirst - 1), j, color, true);
      if (std::max(a, holeLast + 1) <= b) box(std::max(a, holeLast + 1), j, b, j, color, true);
    }
  }

  // A thick segment (a, b already scaled): a rotated rectangle, with round caps if asked.
  void capsule(Vec a, Vec b, double half, bool roundCaps, const Rgba& color, bool clipped) {
    const double length = std::hypot(b.x - a.x, b.y - a.y);
    const Vec n = length > 0 ? Vec{-(b.y - a.y) / length * half, (b.x - a.x) / length * half} : Vec{0, half};
    const std::vector<Vec> body = {{a.x + n.x, a.y + n.y}, {b.x + n.x, b.y + n.y}, {b.x - n.x, b.y - n.y}, {a.x - n.x, a.y - n.y}};
    const double y0 = std::min(a.y, b.y) - half, y1 = std::max(a.y, b.y) + half;
    fillRows(y0, y1, color,
             [&](double y) {
               Span s = length > 0 ? polygonSpan(body, y) : Span{};
               if (roundCaps || length == 0) s = s.join(discSpan(a, half, y)).join(discSpan(b, half, y));
               return s;
             },
             [](double) { return Span{}; }, clipped ? &plot_ : nullptr);
  }

  std::string path_;
  const Rgba background_ = parseColor(kBackground);
  OIIO::ImageBuf buf_;
  Box plot_;  // the plot area, scaled
};

bool hasExtension(const std::string& path, const std::string& wanted) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext == wanted;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::optional<double> Scale::toPixel(double value) const {
  if (!drawable(value, log)) return std::nullopt;
  const double t = log ? (std::log10(value) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (value - lo) / (hi - lo);
  // Far outside the axis still maps to a finite pixel, so clipping code never sees inf.
  return pixelLo + std::clamp(t, -1e6, 1e6) * (pixelHi - pixelLo);
}

std::optional<std::array<double, 2>> Layout::toPixel(double px, double py) const {
  const std::optional<double> a = x.toPixel(px), b = y.toPixel(py);
  if (!a || !b) return std::nullopt;
  return std::array<double, 2>{*a, *b};
}

Layout layoutOf(const Chart& chart, Target target) { return geometryOf(chart, target).layout; }

std::string toSvg(const Chart& chart) {
  const Geometry g = geometryOf(chart, Target::Svg);
  const Layout& L = g.layout;
  const std::string w = std::to_string(chart.width), h = std::to_string(chart.height);
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h + "\" viewBox=\"0 0 " + w + " " + h +
         "\" font-family=\"" + kFontFamily + "\">\n";
  out += "<defs><clipPath id=\"mrr-plot-area\"><rect x=\"" + num(L.left) + "\" y=\"" + num(L.top) + "\" width=\"" +
         num(L.right - L.left) + "\" height=\"" + num(L.bottom - L.top) + "\"/></clipPath></defs>\n";
  out += "<rect width=\"100%\" height=\"100%\" fill=\"" + std::string(kBackground) + "\"/>\n";
  SvgCanvas canvas(out);
  draw(chart, g, canvas);
  out += "</svg>\n";
  return out;
}

void writeSvg(const Chart& chart, const std::string& path) {
  require(hasExtension(path, ".svg"), "cannot write " + path + ": a chart in SVG needs the extension .svg");
  checkOutputLocation(path, "output");
  writeTextFile(path, toSvg(chart));
}

void writePng(const Chart& chart, const std::string& path) {
  require(hasExtension(path, ".png"), "cannot write " + path + ": a chart in PNG needs the extension .png");
  checkOutputLocation(path, "output");  // before drawing, not after
  const Geometry g = geometryOf(chart, Target::Png);
  PngCanvas canvas(g.layout, chart.width, chart.height, path);
  draw(chart, g, canvas);
  // writeImage writes the temporary file and renames it into place (and removes it on failure
  // or on SIGINT); values are display values already, so no sRGB encoding.
  writeImage(path, canvas.finish(chart.width, chart.height));
}

std::vector<size_t> paretoFront(const std::vector<Point>& points) {
  // O(n²): benches have tens of points, and the definition reads off directly.
  const auto finite = [](const Point& p) { return std::isfinite(p.x) && std::isfinite(p.y); };
  std::vector<size_t> front;
  for (size_t i = 0; i < points.size(); ++i) {
    const Point& p = points[i];
    if (!finite(p)) continue;
    bool dominated = false;
    for (size_t j = 0; j < points.size() && !dominated; ++j) {
      const Point& q = points[j];
      dominated = j != i && finite(q) && q.x <= p.x && q.y >= p.y && (q.x < p.x || q.y > p.y);
    }
    if (!dominated) front.push_back(i);
  }
  std::sort(front.begin(), front.end(), [&](size_t a, size_t b) {
    const Point &p = points[a], &q = points[b];
    return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y > q.y : a < b;
  });
  return front;
}

}  // namespace mrr::chart
