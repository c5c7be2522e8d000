#include "compare/parity/html_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <string_view>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/image_io.h"
#include "compare/metrics/flip.h"
#include "common/parallel.h"
#include "common/stage_images.h"
#include "common/stages.h"
#include "common/tolerance.h"
#include "compare/metrics/false_colour.h"
#include "compare/report/report_python.h"

namespace mrr {

namespace {

// ---------------------------------------------------------------------------------------------
// Figures as the page shows them (JSON cannot carry inf or NaN, and the page shows them).

std::string format(const char* fmt, double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  if (std::isnan(value)) return "nan";
  char text[64];
  std::snprintf(text, sizeof text, fmt, value);
  return text;
}

std::string num(double value) { return format("%.3g", value); }

std::string percent(double share) { return format("%.3f", 100.0 * share); }

const ToleranceRule* findRule(std::string_view name) {
  for (const ToleranceRule& r : kTolerances)
    if (r.stage == name) return &r;
  return nullptr;
}

// ---------------------------------------------------------------------------------------------
// Display images.

uint8_t byteOf(float v) {
  if (!(v > 0.0f)) return 0;  // NaN and negatives
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(v * 255.0f));
}

// 1 channel → grey; 2 → R, G, 0; 3 or more → the first three. `map` takes a value to [0, 1].
ImageU8 display(const ImageF& src, const std::function<float(float)>& map) {
  const int channels = src.channels == 1 ? 1 : 3;
  ImageU8 out(src.width, src.height, channels, 0);
  const int copied = std::min(src.channels, 3);
  for (int y = 0; y < src.height; ++y)
    for (int x = 0; x < src.width; ++x)
      for (int c = 0; c < copied; ++c) out.at(x, y, c) = byteOf(map(src.at(x, y, c)));
  return out;
}

ImageU8 displayClamped(const ImageF& src) {
  return display(src, [](float v) { return v; });
}

// Channel `c` of `src`: 0 black, anything else white.
ImageU8 displayBinary(const ImageF& src, int c) {
  ImageU8 out(src.width, src.height, 1, 0);
  for (size_t i = 0; i < out.data.size(); ++i)
    out.data[i] = src.data[i * static_cast<size_t>(src.channels) + static_cast<size_t>(c)] != 0.0f ? 255 : 0;
  return out;
}

// Channel `c` of `src`, small integers (levels, tile rates): one ramp colour each, as explore shows them.
ImageU8 displayLevels(const ImageF& src, int c) {
  ImageU8 out(src.width, src.height, 3, 0);
  for (size_t i = 0; i < src.pixelCount(); ++i) {
    const float level = src.data[i * static_cast<size_t>(src.channels) + static_cast<size_t>(c)];
    rampColour(0.15 + 0.8 * level / 3.0, &out.data[i * 3]);
  }
  return out;
}

// Channel 0 of `src` on the ramp over [lo, hi]; NaN black.
ImageU8 displayRamp(const ImageF& src, float lo, float hi) {
  ImageU8 out(src.width, src.height, 3, 0);
  const float span = hi > lo ? hi - lo : 1.0f;
  for (size_t i = 0; i < src.pixelCount(); ++i) {
    const float v = src.data[i * static_cast<size_t>(src.channels)];
    if (!std::isnan(v)) rampColour((v - lo) / span, &out.data[i * 3]);
  }
  return out;
}

// Point-sampled (display images) or max-pooled (|Δ|, so that no difference vanishes) by an
// integer factor.
ImageU8 shrink(const ImageU8& src, int factor) {
  if (factor <= 1 || src.empty()) return src;
  ImageU8 out((src.width + factor - 1) / factor, (src.height + factor - 1) / factor, src.channels, 0);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < src.channels; ++c) out.at(x, y, c) = src.at(x * factor, y * factor, c);
  return out;
}

ImageF shrinkMax(const ImageF& src, int factor) {
  if (factor <= 1 || src.empty()) return src;
  ImageF out((src.width + factor - 1) / factor, (src.height + factor - 1) / factor, 1, 0.0f);
  for (int y = 0; y < src.height; ++y)
    for (int x = 0; x < src.width; ++x) {
      float& o = out.at(x / factor, y / factor);
      o = std::max(o, src.at(x, y));
    }
  return out;
}

// Per-pixel max over channels of |a − b| where `include(i)` (all pixels when empty); a NaN
// difference counts as infinite. Empty when the sizes differ.
ImageF absDiff(const ImageF& a, const ImageF& b, const std::function<bool(size_t)>& include = {}) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.empty()) return {};
  ImageF out(a.width, a.height, 1, 0.0f);
  const size_t ch = static_cast<size_t>(a.channels);
  for (size_t p = 0; p < out.data.size(); ++p) {
    if (include && !include(p)) continue;
    float worst = 0.0f;
    for (size_t c = 0; c < ch; ++c) {
      const float d = std::fabs(a.data[p * ch + c] - b.data[p * ch + c]);
      worst = std::max(worst, std::isnan(d) ? std::numeric_limits<float>::infinity() : d);
    }
    out.data[p] = worst;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// What one stage row shows.

struct StageView {
  std::string missing;  // why there are no images (empty when there are)
  ImageU8 oracle, port;
  ImageF delta;              // |Δ| per pixel, in the stage's own unit, on the stage's grid
  std::string valueCaption;  // how the stage's values are shown
  std::string deltaCaption;  // what |Δ| is
  bool binary = false;       // a 0/1 stage
  int gridW = 0, gridH = 0;  // the stage's own grid (the worst pixel's coordinates)
  int shrinkLimit = 1280;    // larger images are shown shrunk by an integer factor
};

std::string gridText(int w, int h) { return std::to_string(w) + "×" + std::to_string(h); }

bool sameSize(const ImageF& a, const ImageF& b) { return a.width == b.width && a.height == b.height; }

StageView missingView(bool oracleMissing) {
  StageView v;
  v.missing = "not rendered on " + std::string(oracleMissing ? "the oracle" : "the port");
  return v;
}

// Channel `c` of two 0/1 images.
StageView binaryView(const ImageF& o, const ImageF& p, int c, const std::string& caption) {
  if (o.empty() || p.empty()) return missingView(o.empty());
  StageView v;
  v.oracle = displayBinary(o, c);
  v.port = displayBinary(p, c);
  v.delta = o.channels == p.channels ? absDiff(imageChannel(o, c), imageChannel(p, c)) : ImageF();
  v.binary = true;
  v.gridW = o.width;
  v.gridH = o.height;
  v.valueCaption = caption;
  v.deltaCaption = "|Δ| of a 0/1 image: every mismatch at full scale";
  return v;
}

StageView gbufferView(const GBuffer& o, const GBuffer& p, const std::string& part) {
  if (part == "hit") return binaryView(toFloat(o.hit), toFloat(p.hit), 0, "hit (1 = geometry): 1 white, 0 black");
  StageView v;
  if (o.depth.empty() || p.depth.empty()) {
    v.missing = "not rendered on " + std::string(o.depth.empty() ? "the oracle" : "the port");
    return v;
  }
  if (!sameSize(o.depth, p.depth) || o.hit.data.size() != p.hit.data.size()) {
    v.missing = "the two G-buffers differ in size";
    return v;
  }
  const auto bothHit = [&](size_t i) { return o.hit.data[i] && p.hit.data[i]; };
  v.gridW = o.width;
  v.gridH = o.height;
  ImageF delta(o.width, o.height, 1, 0.0f);
  if (part == "depth") {
    float maxDepth = 0.0f;
    for (size_t i = 0; i < o.depth.data.size(); ++i)
      if (o.hit.data[i] && std::isfinite(o.depth.data[i])) maxDepth = std::max(maxDepth, o.depth.data[i]);
    const float norm = maxDepth > 0.0f ? maxDepth : 1.0f;
    const auto show = [&](const GBuffer& g) {
      ImageF d(g.width, g.height, 1, 0.0f);
      for (size_t i = 0; i < d.data.size(); ++i) d.data[i] = g.hit.data[i] ? g.depth.data[i] / norm : 0.0f;
      return displayClamped(d);
    };
    v.oracle = show(o);
    v.port = show(p);
    for (size_t i = 0; i < delta.data.size(); ++i)
      if (bothHit(i)) delta.data[i] = std::fabs(p.depth.data[i] - o.depth.data[i]) / std::max(o.depth.data[i], 1e-30f);
    v.valueCaption = "linear view depth ÷ " + num(norm) + " (the oracle's largest over hit pixels); background black";
    v.deltaCaption = "relative |Δz|/z where both hit";
  } else if (part == "normal") {
    const auto show = [&](const GBuffer& g) {
      ImageF n(g.width, g.height, 3, 0.0f);
      for (size_t i = 0; i < g.hit.data.size(); ++i)
        if (g.hit.data[i])
          for (size_t c = 0; c < 3; ++c) n.data[i * 3 + c] = 0.5f + 0.5f * g.normal.data[i * 3 + c];
      return displayClamped(n);
    };
    v.oracle = show(o);
    v.port = show(p);
    for (size_t i = 0; i < delta.data.size(); ++i) {
      if (!bothHit(i)) continue;
      float dot = 0.0f;
      for (size_t c = 0; c < 3; ++c) dot += o.normal.data[i * 3 + c] * p.normal.data[i * 3 + c];
      delta.data[i] = std::fabs(1.0f - dot);
    }
    v.valueCaption = "view-space normal as 0.5 + 0.5·n (RGB); background black";
    v.deltaCaption = "1 − N·N′ where both hit";
  } else if (part == "albedo" || part == "position") {
    const bool albedo = part == "albedo";
    float range = 1.0f;  // positions: shown as |P| ÷ the oracle's largest, like depth
    if (!albedo)
      for (size_t i = 0; i < o.hit.data.size(); ++i)
        if (o.hit.data[i])
          for (size_t c = 0; c < 3; ++c) range = std::max(range, std::fabs(o.position.data[i * 3 + c]));
    const auto show = [&](const GBuffer& g) {
      ImageF img(g.width, g.height, 3, 0.0f);
      for (size_t i = 0; i < g.hit.data.size(); ++i)
        if (g.hit.data[i])
          for (size_t c = 0; c < 3; ++c)
            img.data[i * 3 + c] = albedo ? g.albedo.data[i * 3 + c] : 0.5f + 0.5f * g.position.data[i * 3 + c] / range;
      return displayClamped(img);
    };
    v.oracle = show(o);
    v.port = show(p);
    for (size_t i = 0; i < delta.data.size(); ++i) {
      if (!bothHit(i)) continue;
      float d = 0.0f;
      for (size_t c = 0; c < 3; ++c) {
        const size_t k = i * 3 + c;
        d = std::max(d, albedo ? std::fabs(p.albedo.data[k] - o.albedo.data[k])
                               : std::fabs(p.position.data[k] - o.position.data[k]) / std::max(o.depth.data[i], 1e-30f));
      }
      delta.data[i] = d;
    }
    v.valueCaption = albedo ? "base colour (linear RGB); background black"
                            : "view-space position as 0.5 + 0.5·P ÷ " + num(range) + " (RGB); background black";
    v.deltaCaption = albedo ? "largest |Δ| over R, G, B where both hit" : "largest |ΔP| ÷ z where both hit";
  } else {
    v.missing = "no image for G-buffer part \"" + part + "\"";
    return v;
  }
  v.delta = std::move(delta);
  return v;
}

StageView shadowMapView(const ShadowMap& o, const ShadowMap& p) {
  StageView v;
  if (o.depth.empty() || p.depth.empty()) {
    v.missing = "no shadow map on " + std::string(o.depth.empty() ? "the oracle" : "the port");
    return v;
  }
  if (!sameSize(o.depth, p.depth)) {
    v.missing = "the two shadow maps differ in size";
    return v;
  }
  const auto miss = [](float d) { return d == ShadowMap::kNoBlocker || !std::isfinite(d); };
  float lo = std::numeric_limits<float>::max(), hi = 0.0f;
  for (const float d : o.depth.data)
    if (!miss(d)) lo = std::min(lo, d), hi = std::max(hi, d);
  if (lo > hi) lo = hi = 0.0f;
  const float range = hi > lo ? hi - lo : 1.0f;
  const auto show = [&](const ShadowMap& m) {
    ImageF s(m.depth.width, m.depth.height, 1, 0.0f);
    for (size_t i = 0; i < s.data.size(); ++i)
      if (!miss(m.depth.data[i])) s.data[i] = 0.2f + 0.8f * std::clamp((m.depth.data[i] - lo) / range, 0.0f, 1.0f);
    return displayClamped(s);
  };
  v.oracle = show(o);
  v.port = show(p);
  const float texel = o.texel > 0.0f ? o.texel : 1.0f;
  ImageF delta(o.depth.width, o.depth.height, 1, 0.0f);
  for (size_t i = 0; i < delta.data.size(); ++i) {
    const bool mo = miss(o.depth.data[i]), mp = miss(p.depth.data[i]);
    if (mo && mp) continue;
    delta.data[i] =
        mo != mp ? std::numeric_limits<float>::infinity() : std::fabs(p.depth.data[i] - o.depth.data[i]) / texel;
  }
  v.delta = std::move(delta);
  v.gridW = o.depth.width;
  v.gridH = o.depth.height;
  v.shrinkLimit = 512;
  v.valueCaption = "distance from the light plane, " + num(lo) + " → 0.2 … " + num(hi) +
                   " → 1 (the oracle's range); no blocker black";
  v.deltaCaption = "|Δ| in texels where either map has a blocker (one side only: full scale)";
  return v;
}

// One edge kind (a channel of the edges part, named by the row: "edges.depth"; "edges" is E).
StageView edgesView(const FrameResult& o, const FrameResult& p, const std::string& kind) {
  const ImageF a = readPart(o, Part::Edges), b = readPart(p, Part::Edges);
  if (a.empty() || b.empty()) return missingView(a.empty());
  const std::string channel = kind == partName(Part::Edges) ? "E" : kind;
  const std::vector<std::string> names = partChannels(Part::Edges, a);
  const auto at = std::find(names.begin(), names.end(), channel);
  StageView none;
  if (at == names.end() || a.channels != b.channels) {
    none.missing = "no edge kind \"" + kind + "\" on both paths";
    return none;
  }
  const std::string caption = channel == "E"            ? viewCaption(Part::Edges, 1)
                              : channel == "normal"     ? "normal edges (first derivative of N)"
                              : channel == "depth"      ? "depth edges (second derivative of 1/z)"
                              : channel == "background" ? "background edges (a background 4-neighbour)"
                                                        : "shadow edges (the one-tap test differs)";
  return binaryView(a, b, static_cast<int>(at - names.begin()), caption + ": 1 white, 0 black");
}

// A part as its row shows it (common/stages.h PartView), both sides read by the row's accessor.
StageView partView(Part part, int level, const FrameResult& o, const FrameResult& p) {
  const PartView& shown = partInfo(part).view;
  const ImageF a = readPart(o, part, level), b = readPart(p, part, level);
  if (a.empty() || b.empty()) return missingView(a.empty());
  if (shown.display == Display::Binary) return binaryView(a, b, shown.channel, viewCaption(part, a.channels));
  StageView v;
  v.gridW = a.width;
  v.gridH = a.height;
  v.valueCaption = viewCaption(part, a.channels);
  std::function<bool(size_t)> include;
  std::string where;
  if (shown.shadedOnly) {  // |Δ| where both stencils shade: elsewhere nothing was evaluated
    const ImageF so = readPart(o, Part::Stencil, level), sp = readPart(p, Part::Stencil, level);
    if (so.data.size() == a.pixelCount() && sp.data.size() == a.pixelCount()) {
      include = [so, sp](size_t i) { return so.data[i] != 0.0f && sp.data[i] != 0.0f; };
      where = " where both stencils shade";
    }
  }
  v.delta = absDiff(a, b, include);
  v.deltaCaption = "|Δ| = max over channels of |port − oracle|" + where;
  switch (shown.display) {
    case Display::Levels:
      v.oracle = displayLevels(a, shown.channel);
      v.port = displayLevels(b, shown.channel);
      v.binary = true;  // a level or rate: any mismatch at full scale
      v.deltaCaption += "; every mismatch at full scale";
      break;
    case Display::Scalar: {
      float lo = shown.lo, hi = shown.hi;
      if (!(hi > lo)) {  // the oracle's finite range
        lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
        for (size_t i = 0; i < a.pixelCount(); ++i)
          if (const float x = a.data[i * static_cast<size_t>(a.channels)]; std::isfinite(x))
            lo = std::min(lo, x), hi = std::max(hi, x);
        if (lo > hi) lo = hi = 0.0f;
      }
      v.oracle = displayRamp(a, lo, hi);
      v.port = displayRamp(b, lo, hi);
      break;
    }
    case Display::Colour:
      v.oracle = displayClamped(linearToDisplay(a));
      v.port = displayClamped(linearToDisplay(b));
      break;
    default:  // the effect's values
      v.oracle = displayClamped(a);
      v.port = displayClamped(b);
      break;
  }
  return v;
}

StageView viewFor(const StageRow& row, const FrameResult& o, const FrameResult& p) {
  const std::string& stage = row.stage;
  const int l = row.level;
  const bool hasLevel = l >= 0 && l < kLevelCount;
  StageView none;
  Part part{};
  if (!partOf(stage, part)) {  // a decision row (fallback): no image
    none.missing = "no images for stage " + stage;
    return none;
  }
  if (partInfo(part).perLevel && !hasLevel) {
    none.missing = "no level for stage " + stage;
    return none;
  }
  switch (partInfo(part).view.display) {  // the multi-channel parts' own views
    case Display::GBuffer:
      return gbufferView(o.levels[static_cast<size_t>(l)].gbuffer, p.levels[static_cast<size_t>(l)].gbuffer,
                         stage.substr(stage.rfind('.') + 1));
    case Display::ShadowMap: return shadowMapView(o.shadowMap, p.shadowMap);
    case Display::Edges: return edgesView(o, p, stage.substr(stage.find('.') + 1));
    default: return partView(part, hasLevel ? l : -1, o, p);
  }
}

// The check whose worst pixel a row reports: the failing one (the same-input check first
// for a FAIL, the end-to-end check for UPSTREAM), else the end-to-end check.
const StageCheck* worstCheck(const StageRow& row, const std::string& verdict) {
  if (verdict == "FAIL" && row.sameInput && !row.sameInput->pass) return &*row.sameInput;
  if (verdict == "FAIL" && row.endToEnd && !row.endToEnd->pass) return &*row.endToEnd;
  if (row.endToEnd) return &*row.endToEnd;
  return row.sameInput ? &*row.sameInput : nullptr;
}


// ---------------------------------------------------------------------------------------------
// The page's data, shown by compare/report/templates/compare.html.j2.

std::string pixelText(int x, int y) { return x >= 0 ? std::to_string(x) + "," + std::to_string(y) : "–"; }

nlohmann::json checkData(const std::optional<StageCheck>& c) {
  if (!c) return nullptr;
  const DiffFigures& f = c->figures;
  const ToleranceRule* rule = findRule(c->rule);
  return {{"rule", c->rule},
          {"pass", c->pass},
          {"pixels", f.pixels},
          {"max_abs", num(f.maxAbs)},
          {"over", percent(f.shareOver)},
          {"rms", num(f.rms)},
          {"allowed", rule ? percent(rule->shareOver) : "?"},
          {"rms_bound", rule ? (std::isinf(rule->rmsBound) ? "–" : num(rule->rmsBound)) : "?"},
          {"threshold", rule ? num(rule->pixelThreshold) : "?"},
          {"worst", pixelText(f.worstX, f.worstY)},
          {"why", rule ? std::string(rule->why) : ""}};
}

// The heat map's full scale and what it means.
std::pair<double, std::string> heatScale(const StageRow& row, const StageView& v, bool sameInputMap) {
  float top = 0.0f;
  for (const float d : v.delta.data)
    if (std::isfinite(d)) top = std::max(top, d);
  if (v.binary) return {1.0, "black = 0, full scale = 1 (a mismatch)"};
  if (sameInputMap) {
    const double scale = top > 0.0f ? top : 1.0;
    return {scale, "|port − the oracle's function on the port's own inputs| (the failing same-input check); "
                   "black = 0, full scale = " + num(scale) + " = the largest |Δ| here"};
  }
  if (row.endToEnd && findRule(row.endToEnd->rule)) {
    const double threshold = findRule(row.endToEnd->rule)->pixelThreshold;
    return {10.0 * threshold, "black = 0, full scale = " + num(10.0 * threshold) + " = 10 × the " +
                                  row.endToEnd->rule + " threshold (" + num(threshold) + ")"};
  }
  if (top > 0.0f) return {top, "black = 0, full scale = " + num(top) + " = the largest |Δ| here (normalised to the max)"};
  return {1.0, "no difference anywhere"};
}

// The worst pixel of a row that did not pass (and of the final row): where, by which check,
// and the `mrr probe` command that follows it. Null when the row has no check.
nlohmann::json worstData(const StageRow& row, const std::string& verdict, const ComparedFrame& frame) {
  const StageCheck* source = worstCheck(row, verdict);
  if (!source) return nullptr;
  const int gx = source->figures.worstX, gy = source->figures.worstY;
  const bool probe = row.scale > 0 && gx >= 0;  // shadow-map texels (scale 0) are no screen pixels
  const int width = frame.oracle->constants.width, height = frame.oracle->constants.height;
  const int x = probe ? std::clamp(gx * row.scale + row.scale / 2, 0, std::max(width - 1, 0)) : -1;
  const int y = probe ? std::clamp(gy * row.scale + row.scale / 2, 0, std::max(height - 1, 0)) : -1;
  return {{"check", row.sameInput && source == &*row.sameInput ? "same-input" : "end-to-end"},
          {"rule", source->rule},
          {"max_abs", num(source->figures.maxAbs)},
          {"grid_x", gx},
          {"grid_y", gy},
          {"probe", probe},
          {"x", x},
          {"y", y},
          {"command", probe ? frame.probeCommand + " --pixel " + pixelText(x, y) : ""}};
}

// An 8-bit display image as a PNG (writeImage takes floats in [0, 1]; n/255 comes back as n).
void writeDisplayPng(const std::string& path, const ImageU8& image) {
  ImageF scaled(image.width, image.height, image.channels);
  for (size_t i = 0; i < image.data.size(); ++i) scaled.data[i] = static_cast<float>(image.data[i]) / 255.0f;
  writeImage(path, scaled);
}

}  // namespace

void writeCompareReport(const std::string& dir, const CompareReportInfo& info,
                        const std::vector<ComparedFrame>& frames) {
  const ReportJob job;
  // Every image, written into the scratch folder once all are known (in parallel); the page
  // embeds them.
  std::vector<std::pair<std::string, ImageU8>> images;
  const auto add = [&](ImageU8 image) -> nlohmann::json {
    if (image.empty()) return nullptr;
    const std::string file = "image" + std::to_string(images.size()) + ".png";
    nlohmann::json ref = {{"file", file}, {"width", image.width}, {"height", image.height}};
    images.emplace_back(file, std::move(image));
    return ref;
  };

  nlohmann::json frameData = nlohmann::json::array();
  for (const ComparedFrame& frame : frames) {
    if (!frame.oracle || !frame.port) throw MrrError("--report: frame " + frame.effect + " has no images to show");
    nlohmann::json rows = nlohmann::json::array();
    for (const StageRow& row : frame.result.rows) {
      const std::string verdict = row.verdict();
      StageView v = viewFor(row, *frame.oracle, *frame.port);
      nlohmann::json r = {{"stage", row.stage}, {"verdict", verdict},  {"level", row.level},
                          {"scale", row.scale}, {"missing", v.missing}, {"grid_w", v.gridW},
                          {"grid_h", v.gridH},  {"oracle_image", nullptr}, {"port_image", nullptr},
                          {"heat_image", nullptr}, {"flip_image", nullptr}, {"end_to_end", checkData(row.endToEnd)},
                          {"same_input", checkData(row.sameInput)}, {"worst", nullptr}};
      if (verdict != "PASS" || row.stage == partName(Part::Final)) r["worst"] = worstData(row, verdict, frame);
      if (v.missing.empty()) {
        // A stage that fails on the port's own inputs: show what that check measured — the
        // port against the oracle's function on the same inputs — not the end-to-end difference.
        const bool sameInputMap = verdict == "FAIL" && row.sameInput && !row.sameInput->pass &&
                                  !row.sameInput->figures.deltaMap.empty();
        if (sameInputMap) v.delta = row.sameInput->figures.deltaMap;
        auto [scale, heatCaption] = heatScale(row, v, sameInputMap);
        const int factor = std::max(1, (std::max(v.gridW, v.gridH) + v.shrinkLimit - 1) / v.shrinkLimit);
        if (factor > 1) {
          const std::string f = std::to_string(factor);
          heatCaption += "; shown ÷" + f + " (max over each " + f + "×" + f + " block)";
          v.valueCaption += "; shown at " + gridText((v.gridW + factor - 1) / factor, (v.gridH + factor - 1) / factor) +
                            " (every " + f + "th texel)";
        }
        r["oracle_image"] = add(shrink(v.oracle, factor));
        r["port_image"] = add(shrink(v.port, factor));
        if (!v.delta.empty()) r["heat_image"] = add(heatMap(shrinkMax(v.delta, factor), scale));
        // The final image and the shaded one: the LDR-FLIP map of the port against the oracle
        // beside |Δ| (the effect as grey, the shaded image as its display values, as the bench).
        if (row.stage == partName(Part::Final) || row.stage == partName(Part::Shaded)) {
          const bool shaded = row.stage == partName(Part::Shaded);
          const FlipResult f = shaded ? flip(linearToDisplay(frame.oracle->shaded), linearToDisplay(frame.port->shaded))
                                      : flip(frame.oracle->final(), frame.port->final());
          r["flip_image"] = add(flipColourMapBytes(shrinkMax(f.errorMap, factor)));
          r["flip_mean"] = num(f.stats.mean);
          r["flip_max"] = num(f.stats.max);
          r["flip_caption"] = std::string(shaded ? "the shaded image's display values (sRGB, clamped)"
                                                 : "the effect buffer as grey, clamped to [0, 1]") +
                              ", at " + num(kFlipDefaultPpd) + " pixels per degree; black = 0, pale yellow = 1" +
                              (factor > 1 ? "; shown ÷" + std::to_string(factor) + " (max over each block)" : "");
        }
        r["heat_scale"] = num(scale);
        r["heat_caption"] = heatCaption;
        r["value_caption"] = v.valueCaption;
        r["delta_caption"] = v.deltaCaption;
      }
      rows.push_back(std::move(r));
    }
    frameData.push_back({{"effect", frame.effect},
                         {"pass", frame.result.pass()},
                         {"first_failing", frame.result.firstFailing()},
                         {"inherited", frame.result.inherited()},
                         {"rows", std::move(rows)}});
  }
  parallelFor(size_t{0}, images.size(), [&](size_t i) {
    writeDisplayPng(job.folder() + "/" + images[i].first, images[i].second);
    images[i].second = {};
  });

  std::string frameText;
  if (!frames.empty()) {
    const Constants& c = frames.front().oracle->constants;
    frameText = gridText(c.width, c.height) + " (padded " + gridText(c.paddedWidth, c.paddedHeight) + "), mode " +
                toString(c.mode);
  }
  const nlohmann::json data = {{"kind", "compare"},
                               {"title", std::filesystem::path(info.scene).filename().string()},
                               {"scene", info.scene},
                               {"credit", info.credit},
                               {"renderer", info.renderer},
                               {"subject", info.subject},
                               {"command", info.command},
                               {"frame", frameText},
                               {"ramp", rampGradient()},
                               {"magma", flipMagmaGradient()},
                               {"frames", std::move(frameData)}};
  writeTextFile((std::filesystem::path(dir) / "index.html").string(), job.makePage(data));
}

}  // namespace mrr
