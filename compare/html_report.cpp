#include "compare/html_report.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <sstream>
#include <string_view>

#include "common/error.h"
#include "common/image_io.h"
#include "common/parallel.h"
#include "common/tolerance.h"

namespace mrr {

namespace {

// ---------------------------------------------------------------------------------------------
// Text helpers.

std::string escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

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

// The anchor of one stage section: "<effect>-<stage>" (stage names hold only [a-z0-9.]).
std::string anchor(const std::string& effect, const std::string& stage) { return effect + "-" + stage; }

std::string base64(const std::vector<unsigned char>& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (unsigned{bytes[i]} << 16) | (unsigned{bytes[i + 1]} << 8) | unsigned{bytes[i + 2]};
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const unsigned v = (unsigned{bytes[i]} << 16) | (two ? unsigned{bytes[i + 1]} << 8 : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += two ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// An 8-bit grey or RGB image as an in-memory PNG (OpenImageIO, through an IOProxy).
std::string oneLine(std::string message) {
  for (char& ch : message)
    if (ch == '\n' || ch == '\r') ch = ' ';
  return message.empty() ? std::string("unknown OpenImageIO error") : message;
}

std::vector<unsigned char> encodePng(const ImageU8& image) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("report.png", &proxy);
  if (!out) throw MrrError("--report: cannot encode a PNG: " + oneLine(OIIO::geterror()));
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
  spec.alpha_channel = -1;
  spec.attribute("png:compressionLevel", 9);
  spec.attribute("DateTime", "");
  const auto fail = [&] { throw MrrError("--report: cannot encode a PNG: " + oneLine(out->geterror())); };
  if (!out->set_ioproxy(&proxy)) fail();
  if (!out->open("report.png", spec)) fail();
  if (!out->write_image(OIIO::TypeDesc::UINT8, image.data.data())) fail();
  if (!out->close()) fail();
  return bytes;
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

ImageU8 displayBinary(const ImageU8& src) {
  ImageU8 out(src.width, src.height, 1, 0);
  for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = src.data[i * static_cast<size_t>(src.channels)] ? 255 : 0;
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

// Inferno-like ramp from black: perceptually ordered, readable in grey.
constexpr std::array<std::array<int, 3>, 9> kRamp = {{{0, 0, 4},
                                                      {31, 12, 72},
                                                      {85, 15, 109},
                                                      {136, 34, 106},
                                                      {186, 54, 85},
                                                      {227, 89, 51},
                                                      {249, 140, 10},
                                                      {249, 201, 50},
                                                      {252, 255, 164}}};

ImageU8 heatMap(const ImageF& delta, double scale) {
  ImageU8 out(delta.width, delta.height, 3, 0);
  for (size_t p = 0; p < delta.pixelCount(); ++p) {
    const double d = delta.data[p];
    if (!(d > 0.0) && !std::isnan(d)) continue;  // exactly 0: black
    const double t = std::isfinite(d) && scale > 0.0 ? std::clamp(d / scale, 0.0, 1.0) : 1.0;
    const double s = t * static_cast<double>(kRamp.size() - 1);
    const size_t i = std::min(static_cast<size_t>(s), kRamp.size() - 2);
    const double f = s - static_cast<double>(i);
    for (size_t c = 0; c < 3; ++c) {
      const double v = (1.0 - f) * kRamp[i][c] + f * kRamp[i + 1][c];
      out.data[p * 3 + c] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  }
  return out;
}

std::string rampGradient() {
  std::string css = "linear-gradient(to right";
  for (const auto& c : kRamp)
    css += ",rgb(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
  return css + ")";
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

StageView binaryView(const ImageU8& o, const ImageU8& p, const std::string& what) {
  StageView v;
  if (o.empty() || p.empty()) {
    v.missing = "not rendered on " + std::string(o.empty() ? "the oracle" : "the port");
    return v;
  }
  v.oracle = displayBinary(o);
  v.port = displayBinary(p);
  v.delta = absDiff(toFloat(o), toFloat(p));
  v.binary = true;
  v.gridW = o.width;
  v.gridH = o.height;
  v.valueCaption = what + ": 0 black, 1 white";
  v.deltaCaption = "|Δ| of a 0/1 image: every mismatch at full scale";
  return v;
}

StageView valueView(const ImageF& o, const ImageF& p, const std::string& what,
                    const std::function<bool(size_t)>& include = {}, const std::string& where = {}) {
  StageView v;
  if (o.empty() || p.empty()) {
    v.missing = "not rendered on " + std::string(o.empty() ? "the oracle" : "the port");
    return v;
  }
  v.oracle = displayClamped(o);
  v.port = displayClamped(p);
  v.delta = absDiff(o, p, include);
  v.gridW = o.width;
  v.gridH = o.height;
  v.valueCaption = what + (o.channels == 1 ? "" : " (RGB)") + ", clamped to [0, 1]";
  v.deltaCaption = "|Δ| = max over channels of |port − oracle|" + where;
  return v;
}

StageView gbufferView(const GBuffer& o, const GBuffer& p, const std::string& part) {
  if (part == "hit") return binaryView(o.hit, p.hit, "hit (1 = geometry)");
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

StageView viewFor(const StageRow& row, const FrameResult& o, const FrameResult& p) {
  const std::string& stage = row.stage;
  const std::string kind = stage.substr(0, stage.find('.'));
  const std::string part = stage.substr(stage.rfind('.') + 1);
  const int l = row.level;
  const bool hasLevel = l >= 0 && l < kLevelCount;
  const size_t li = hasLevel ? static_cast<size_t>(l) : 0;
  StageView none;
  const auto needLevel = [&] {
    if (!hasLevel) none.missing = "no level for stage " + stage;
    return hasLevel;
  };
  if (kind == "gbuffer") return needLevel() ? gbufferView(o.levels[li].gbuffer, p.levels[li].gbuffer, part) : none;
  if (kind == "shadowmap") return shadowMapView(o.shadowMap, p.shadowMap);
  if (kind == "shadowtest") return binaryView(o.shadowLit, p.shadowLit, "one-tap shadow test (1 = lit)");
  if (kind == "edges") {
    if (part == "normal") return binaryView(o.edges.normal, p.edges.normal, "normal edges (first derivative of N)");
    if (part == "depth") return binaryView(o.edges.depth, p.edges.depth, "depth edges (second derivative of 1/z)");
    if (part == "background") return binaryView(o.edges.background, p.edges.background, "background edges");
    if (part == "shadow") return binaryView(o.edges.shadow, p.edges.shadow, "shadow edges (one-tap test differs)");
    return binaryView(o.edges.combined, p.edges.combined, "edge image E (the OR of the kinds)");
  }
  if (kind == "mask")
    return needLevel() ? binaryView(o.levels[li].masks.mask, p.levels[li].masks.mask, "mask M_ℓ") : none;
  if (kind == "stencil")
    return needLevel() ? binaryView(o.levels[li].masks.stencil, p.levels[li].masks.stencil, "stencil S_ℓ") : none;
  if (kind == "alpha") return needLevel() ? valueView(o.levels[li].masks.alpha, p.levels[li].masks.alpha, "a_ℓ") : none;
  if (kind == "raw" || kind == "sub") {
    if (!needLevel()) return none;
    const LevelResult& ol = o.levels[li];
    const LevelResult& pl = p.levels[li];
    const ImageF& a = kind == "raw" ? ol.raw : ol.sub;
    const ImageF& b = kind == "raw" ? pl.raw : pl.sub;
    const bool stencils =
        ol.masks.stencil.data.size() == a.pixelCount() && pl.masks.stencil.data.size() == a.pixelCount();
    const auto bothShaded = [&](size_t i) { return ol.masks.stencil.data[i] && pl.masks.stencil.data[i]; };
    return valueView(a, b, kind == "raw" ? "the effect before the blur" : "c_ℓ (after the bilateral blur)",
                     stencils ? std::function<bool(size_t)>(bothShaded) : std::function<bool(size_t)>{},
                     stencils ? " where both stencils shade" : "");
  }
  if (kind == "upsample") return needLevel() ? valueView(o.blend.upsampled[li], p.blend.upsampled[li], "ĉ_ℓ") : none;
  if (kind == "blendalpha") return needLevel() ? valueView(o.blend.alpha[li], p.blend.alpha[li], "α_ℓ") : none;
  if (kind == "composite") return needLevel() ? valueView(o.blend.composite[li], p.blend.composite[li], "c′_ℓ") : none;
  if (kind == "final") return valueView(o.final(), p.final(), "the final effect buffer");
  none.missing = "no images for stage " + stage;
  return none;
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
// The page.

// One image to embed, encoded in parallel once all are known.
struct Embedded {
  ImageU8 image;
  int width = 0, height = 0;
  std::string uri;
};

struct WorstPixel {
  bool shown = false;
  std::string check;  // "end to end" / "same input"
  const StageCheck* source = nullptr;
  int gridX = -1, gridY = -1;
  bool probe = false;
  int x = -1, y = -1;  // full-res
  std::string command;
};

struct RowPage {
  const StageRow* row = nullptr;
  std::string verdict;
  StageView view;
  int oracleImage = -1, portImage = -1, heatImage = -1;
  double heatScale = 0.0;
  std::string heatCaption;
  WorstPixel worst;
};

struct FramePage {
  const ComparedFrame* frame = nullptr;
  std::vector<RowPage> rows;
};

constexpr std::string_view kStyle = R"(
*{box-sizing:border-box}
body{font:14px/1.4 system-ui,-apple-system,"Segoe UI",Roboto,Helvetica,Arial,sans-serif;margin:0;color:#1c1c1c;background:#f4f4f2}
main{max-width:1400px;margin:0 auto;padding:16px 20px 40px}
h1{font-size:22px;margin:4px 0 8px}
h2{font-size:19px;margin:28px 0 8px;padding-top:8px;border-top:2px solid #bbb}
h3{font-size:16px;margin:0 0 6px}
a{color:#1a4fa0}
code,.mono{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,"DejaVu Sans Mono",monospace;font-size:12.5px}
dl.meta{display:grid;grid-template-columns:max-content 1fr;gap:2px 14px;margin:8px 0 12px}
dl.meta dt{font-weight:600;color:#555}
dl.meta dd{margin:0;word-break:break-all}
.overview{display:grid;gap:8px;margin:8px 0 10px}
.ov{display:grid;grid-template-columns:250px repeat(3,minmax(0,300px));gap:10px;align-items:start;background:#fff;border:1px solid #ccc;border-left:6px solid #2e7d32;border-radius:6px;padding:8px 10px}
.ov.FAIL{border-left-color:#c62828}
.ovname{font-size:18px;font-weight:700;margin-bottom:4px}
.v{display:inline-block;font-weight:700;font-size:12px;padding:1px 7px;border-radius:4px;color:#fff}
.v.PASS{background:#2e7d32}.v.FAIL{background:#c62828}.v.UPSTREAM{background:#b26a00}
table{border-collapse:collapse;background:#fff}
th,td{border:1px solid #d4d4d4;padding:2px 7px;text-align:right;white-space:nowrap}
th{background:#ebebeb;font-weight:600}
td.l,th.l{text-align:left}
td.bad{color:#c62828;font-weight:700}
tr.FAIL td:first-child{border-left:4px solid #c62828}
tr.UPSTREAM td:first-child{border-left:4px solid #b26a00}
.scroll{overflow-x:auto}
section.stage{background:#fff;border:1px solid #d4d4d4;border-radius:6px;margin:14px 0;padding:10px 12px}
section.stage.FAIL{border-color:#c62828;box-shadow:0 0 0 2px #f3c2c2}
section.stage.UPSTREAM{border-color:#d9a441}
.trio{display:grid;grid-template-columns:repeat(3,minmax(0,1fr));gap:10px;margin:6px 0}
figure{margin:0}
figcaption{font-size:12px;color:#444;margin-top:3px}
.wrap{position:relative;line-height:0;background:#000}
.wrap img{width:100%;height:auto;image-rendering:crisp-edges;image-rendering:pixelated;display:block}
.mark{position:absolute;min-width:12px;min-height:12px;transform:translate(-50%,-50%);border:2px solid #00e5ff;outline:1px solid #000;pointer-events:none}
.ramp{display:inline-block;width:90px;height:9px;vertical-align:middle;border:1px solid #888;margin:0 4px}
.missing{color:#777;font-style:italic}
code.cmd{display:block;user-select:all;background:#f1f3f6;border:1px solid #d0d5dd;padding:4px 6px;margin:3px 0;white-space:pre-wrap;word-break:break-all}
.small{font-size:12px;color:#555}
)";

std::string verdictBadge(const std::string& verdict) {
  return "<span class=\"v " + escape(verdict) + "\">" + escape(verdict) + "</span>";
}

std::string checkCells(const std::optional<StageCheck>& c) {
  if (!c) return "<td class=\"l\">–</td><td></td><td></td><td></td><td></td>";
  const DiffFigures& f = c->figures;
  const ToleranceRule* rule = findRule(c->rule);
  const std::string bad = c->pass ? "" : " class=\"bad\"";
  std::string title = rule ? " title=\"" + escape(rule->why) + "\"" : "";
  return "<td class=\"l\"" + title + ">" + escape(c->rule) + (c->pass ? "" : " ✗") + "</td><td>" +
         std::to_string(f.pixels) + "</td><td>" + num(f.maxAbs) + "</td><td" + bad + ">" + percent(f.shareOver) +
         "</td><td" + bad + ">" + num(f.rms) + "</td>";
}

std::string checkTableRow(const std::string& name, const std::optional<StageCheck>& c) {
  if (!c) return {};
  const DiffFigures& f = c->figures;
  const ToleranceRule* rule = findRule(c->rule);
  std::string out = "<tr><td class=\"l\">" + name + "</td><td class=\"l\">" + escape(c->rule) +
                    "</td><td class=\"l\">" + (c->pass ? "pass" : "<b style=\"color:#c62828\">fail</b>") + "</td><td>" +
                    std::to_string(f.pixels) + "</td><td>" + num(f.maxAbs) + "</td><td>" + percent(f.shareOver) +
                    "</td><td>" + (rule ? percent(rule->shareOver) : "?") + "</td><td>" + num(f.rms) + "</td><td>" +
                    (rule ? (std::isinf(rule->rmsBound) ? std::string("–") : num(rule->rmsBound)) : "?") + "</td><td>" +
                    (rule ? num(rule->pixelThreshold) : "?") + "</td><td>" +
                    (f.worstX >= 0 ? std::to_string(f.worstX) + "," + std::to_string(f.worstY) : "–") +
                    "</td><td class=\"l small\" style=\"white-space:normal\">" + (rule ? escape(rule->why) : "") +
                    "</td></tr>\n";
  return out;
}

std::string markStyle(const RowPage& r) {
  const double w = r.view.gridW, h = r.view.gridH;
  char style[200];
  std::snprintf(style, sizeof style, "left:%.4f%%;top:%.4f%%;width:%.4f%%;height:%.4f%%",
                100.0 * (r.worst.gridX + 0.5) / w, 100.0 * (r.worst.gridY + 0.5) / h, 100.0 / w + 0.0, 100.0 / h + 0.0);
  return style;
}

std::string worstText(const RowPage& r) {
  const WorstPixel& w = r.worst;
  if (w.gridX < 0) return "<span class=\"missing\">no pixel compared</span>";
  std::string text = "largest |Δ| of its " + w.check + " check (" + escape(w.source->rule) + ": " +
                     num(w.source->figures.maxAbs) + ") at ";
  if (!w.probe)
    return text + "texel " + std::to_string(w.gridX) + "," + std::to_string(w.gridY) +
           " of the shadow map (no probe: <code>mrr probe</code> follows screen pixels)";
  text += "grid pixel " + std::to_string(w.gridX) + "," + std::to_string(w.gridY) + " = full-res pixel <b>" +
          std::to_string(w.x) + "," + std::to_string(w.y) + "</b>; probe it:";
  return text + "<code class=\"cmd\">" + escape(w.command) + "</code>";
}

}  // namespace

void writeCompareReport(const std::string& dir, const CompareReportInfo& info,
                        const std::vector<ComparedFrame>& frames) {
  const std::string path = (std::filesystem::path(dir) / "index.html").string();
  std::vector<Embedded> images;
  const auto add = [&](ImageU8 image) {
    if (image.empty()) return -1;
    const int w = image.width, h = image.height;
    images.push_back({std::move(image), w, h, {}});
    return static_cast<int>(images.size()) - 1;
  };

  // 1. Every row's images and worst pixel.
  std::vector<FramePage> pages;
  for (const ComparedFrame& frame : frames) {
    if (!frame.oracle || !frame.port) throw MrrError("--report: frame " + frame.effect + " has no images to show");
    FramePage page{&frame, {}};
    const int width = frame.oracle->constants.width, height = frame.oracle->constants.height;
    for (const StageRow& row : frame.result.rows) {
      RowPage r;
      r.row = &row;
      r.verdict = row.verdict();
      r.view = viewFor(row, *frame.oracle, *frame.port);
      StageView& v = r.view;
      // A stage that fails on the port's own inputs: show what that check measured — the port
      // against the oracle's function on the same inputs — not the end-to-end difference.
      const bool sameInputMap = r.verdict == "FAIL" && row.sameInput && !row.sameInput->pass &&
                                !row.sameInput->figures.deltaMap.empty() && v.missing.empty();
      if (sameInputMap) v.delta = row.sameInput->figures.deltaMap;
      if (v.missing.empty()) {
        const int factor = std::max(1, (std::max(v.gridW, v.gridH) + v.shrinkLimit - 1) / v.shrinkLimit);
        if (v.binary) {
          r.heatScale = 1.0;
          r.heatCaption = "black = 0, full scale = 1 (a mismatch)";
        } else if (sameInputMap) {
          float top = 0.0f;
          for (const float d : v.delta.data)
            if (std::isfinite(d)) top = std::max(top, d);
          r.heatScale = top > 0.0f ? top : 1.0;
          r.heatCaption = "black = 0, full scale = " + num(r.heatScale) + " = the largest |Δ| here";
        } else if (row.endToEnd && findRule(row.endToEnd->rule)) {
          r.heatScale = 10.0 * findRule(row.endToEnd->rule)->pixelThreshold;
          r.heatCaption = "black = 0, full scale = " + num(r.heatScale) + " = 10 × the " + escape(row.endToEnd->rule) +
                          " threshold (" + num(r.heatScale / 10.0) + ")";
        } else {
          float top = 0.0f;
          for (const float d : v.delta.data)
            if (std::isfinite(d)) top = std::max(top, d);
          r.heatScale = top > 0.0f ? top : 1.0;
          r.heatCaption =
              top > 0.0f ? "black = 0, full scale = " + num(top) + " = the largest |Δ| here (normalised to the max)"
                         : "no difference anywhere";
        }
        if (sameInputMap)
          r.heatCaption = "|port − the oracle's function on the port's own inputs| (the failing same-input check); " +
                          r.heatCaption;
        if (factor > 1)
          r.heatCaption += "; shown ÷" + std::to_string(factor) + " (max over each " + std::to_string(factor) + "×" +
                           std::to_string(factor) + " block)";
        r.oracleImage = add(shrink(v.oracle, factor));
        r.portImage = add(shrink(v.port, factor));
        if (!v.delta.empty()) r.heatImage = add(heatMap(shrinkMax(v.delta, factor), r.heatScale));
        if (factor > 1)
          v.valueCaption += "; shown at " + gridText((v.gridW + factor - 1) / factor, (v.gridH + factor - 1) / factor) +
                            " (every " + std::to_string(factor) + "th texel)";
        v.oracle = {};  // encoded from the copies above; only the grid size is needed from here
        v.port = {};
        v.delta = {};
      }
      if (r.verdict != "PASS" || row.stage == "final") {
        WorstPixel& w = r.worst;
        w.shown = true;
        w.source = worstCheck(row, r.verdict);
        if (w.source) {
          w.check = row.sameInput && w.source == &*row.sameInput ? "same-input" : "end-to-end";
          w.gridX = w.source->figures.worstX;
          w.gridY = w.source->figures.worstY;
          w.probe = row.scale > 0 && w.gridX >= 0;
          if (w.probe) {
            w.x = std::clamp(w.gridX * row.scale + row.scale / 2, 0, std::max(width - 1, 0));
            w.y = std::clamp(w.gridY * row.scale + row.scale / 2, 0, std::max(height - 1, 0));
            w.command = frame.probeCommand + " --pixel " + std::to_string(w.x) + "," + std::to_string(w.y);
          }
        } else {
          w.shown = false;
        }
      }
      page.rows.push_back(std::move(r));
    }
    pages.push_back(std::move(page));
  }

  // 2. Encode every image (independent: in parallel).
  parallelFor(size_t{0}, images.size(), [&](size_t i) {
    images[i].uri = "data:image/png;base64," + base64(encodePng(images[i].image));
    images[i].image = {};
  });

  const auto img = [&](int index, const std::string& alt) {
    if (index < 0) return std::string("<p class=\"missing\">no image</p>");
    const Embedded& e = images[static_cast<size_t>(index)];
    return "<img src=\"" + e.uri + "\" width=\"" + std::to_string(e.width) + "\" height=\"" + std::to_string(e.height) +
           "\" alt=\"" + escape(alt) + "\">";
  };

  // 3. The page.
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">\n"
       << "<title>mrr compare: " << escape(std::filesystem::path(info.scene).filename().string()) << "</title>\n"
       << "<style>" << kStyle << ".ramp{background:" << rampGradient() << "}\n</style>\n</head>\n<body>\n<main>\n";
  html << "<h1 id=\"top\">mrr compare: oracle (cpu_ref) against the GL port</h1>\n<dl class=\"meta\">\n"
       << "<dt>scene</dt><dd>" << escape(info.scene) << "</dd>\n"
       << "<dt>credit</dt><dd>" << (info.credit.empty() ? std::string("(none given)") : escape(info.credit))
       << "</dd>\n"
       << "<dt>renderer</dt><dd>" << escape(info.renderer) << "</dd>\n"
       << "<dt>command</dt><dd><code class=\"cmd\">" << escape(info.command) << "</code></dd>\n";
  if (!frames.empty() && frames.front().oracle) {
    const Constants& c = frames.front().oracle->constants;
    html << "<dt>frame</dt><dd>" << gridText(c.width, c.height) << " (padded "
         << gridText(c.paddedWidth, c.paddedHeight) << "), mode " << escape(toString(c.mode)) << "</dd>\n";
  }
  html << "</dl>\n<div class=\"overview\">\n";
  for (const FramePage& page : pages) {
    const ParityResult& result = page.frame->result;
    const std::string first = result.firstFailing();
    const std::string& effect = page.frame->effect;
    html << "<div class=\"ov " << (first.empty() ? "PASS" : "FAIL") << "\" data-effect=\"" << escape(effect)
         << "\"><div class=\"ovtext\"><div class=\"ovname\">" << escape(effect) << " "
         << verdictBadge(first.empty() ? "PASS" : "FAIL") << "</div>";
    if (!first.empty())
      html << "<div>first failing stage <a href=\"#" << escape(anchor(effect, first)) << "\"><b>" << escape(first)
           << "</b></a></div>";
    else
      html << "<div>every stage's own computation within tolerance</div>";
    if (result.inherited() > 0)
      html << "<div class=\"small\">" << result.inherited() << " stage(s) UPSTREAM (over the end-to-end rule by "
           << "what they inherit)</div>";
    html << "<div class=\"small\">" << page.rows.size() << " stages · <a href=\"#" << escape(anchor(effect, "summary"))
         << "\">summary table</a></div></div>\n";
    const auto finalRow =
        std::find_if(page.rows.begin(), page.rows.end(), [](const RowPage& r) { return r.row->stage == "final"; });
    if (finalRow != page.rows.end() && finalRow->view.missing.empty()) {
      const RowPage& r = *finalRow;
      html << "<figure><div class=\"wrap\">" << img(r.oracleImage, effect + " final, oracle")
           << "</div><figcaption>final, <b>oracle</b></figcaption></figure>"
           << "<figure><div class=\"wrap\">" << img(r.portImage, effect + " final, port")
           << "</div><figcaption>final, <b>port</b></figcaption></figure>"
           << "<figure><div class=\"wrap\">" << img(r.heatImage, effect + " final, |Δ|");
      if (r.heatImage >= 0 && r.worst.shown && r.worst.gridX >= 0)
        html << "<span class=\"mark\" style=\"" << markStyle(r) << "\" title=\"worst pixel\"></span>";
      html << "</div><figcaption><a href=\"#" << escape(anchor(effect, "final")) << "\">final</a>, <b>|Δ|</b> "
           << "<span class=\"ramp\"></span> full scale " << num(r.heatScale) << "</figcaption></figure>";
    }
    html << "</div>\n";
  }
  html << "</div>\n<p class=\"small\">A check passes when its over% (share of pixels with |Δ| over the rule's "
          "threshold) and RMS are within the rule's bounds (common/tolerance.h). <b>end to end</b>: the port's stage "
          "against the oracle's; <b>same input</b>: against the oracle's function run on the port's own inputs. "
          "UPSTREAM: over the end-to-end rule while the same-input check passes, so inherited from an earlier "
          "stage. Images: oracle, port, and a heat map of end-to-end |Δ| (black = 0, then the ramp "
          "<span class=\"ramp\"></span>).</p>\n";

  for (const FramePage& page : pages) {
    const std::string& effect = page.frame->effect;
    const ParityResult& result = page.frame->result;
    html << "<h2 id=\"" << escape(anchor(effect, "summary")) << "\">" << escape(effect) << ": "
         << verdictBadge(result.pass() ? "PASS" : "FAIL");
    if (!result.pass())
      html << " first failing stage <a href=\"#" << escape(anchor(effect, result.firstFailing())) << "\">"
           << escape(result.firstFailing()) << "</a>";
    html << "</h2>\n<div class=\"scroll\"><table class=\"summary\">\n"
         << "<tr><th class=\"l\" rowspan=\"2\">stage</th><th class=\"l\" rowspan=\"2\">verdict</th>"
         << "<th colspan=\"5\">end to end</th><th colspan=\"5\">same input</th></tr>\n<tr>";
    for (int k = 0; k < 2; ++k)
      html << "<th class=\"l\">rule</th><th>pixels</th><th>max|Δ|</th><th>over%</th><th>rms</th>";
    html << "</tr>\n";
    for (const RowPage& r : page.rows)
      html << "<tr class=\"" << escape(r.verdict) << "\"><td class=\"l\"><a href=\"#"
           << escape(anchor(effect, r.row->stage)) << "\">" << escape(r.row->stage) << "</a></td><td class=\"l\">"
           << verdictBadge(r.verdict) << "</td>" << checkCells(r.row->endToEnd) << checkCells(r.row->sameInput)
           << "</tr>\n";
    html << "</table></div>\n";

    html << "<h3 style=\"margin-top:14px\">Worst pixels</h3>\n<div class=\"scroll\"><table class=\"worst\">\n"
         << "<tr><th class=\"l\">stage</th><th class=\"l\">verdict</th><th class=\"l\">check</th><th>max|Δ|</th>"
         << "<th>grid pixel</th><th>full-res pixel</th><th class=\"l\">probe</th></tr>\n";
    for (const RowPage& r : page.rows) {
      if (!r.worst.shown) continue;
      const WorstPixel& w = r.worst;
      html << "<tr class=\"" << escape(r.verdict) << "\"><td class=\"l\"><a href=\"#"
           << escape(anchor(effect, r.row->stage)) << "\">" << escape(r.row->stage) << "</a></td><td class=\"l\">"
           << verdictBadge(r.verdict) << "</td><td class=\"l\">" << w.check << " (" << escape(w.source->rule)
           << ")</td><td>" << num(w.source->figures.maxAbs) << "</td><td>"
           << (w.gridX >= 0 ? std::to_string(w.gridX) + "," + std::to_string(w.gridY) : "–") << "</td><td>"
           << (w.probe ? std::to_string(w.x) + "," + std::to_string(w.y) : "–")
           << "</td><td class=\"l\" style=\"white-space:normal\">"
           << (w.probe ? "<code class=\"cmd\">" + escape(w.command) + "</code>"
                       : std::string("<span class=\"small\">no probe (shadow-map texel)</span>"))
           << "</td></tr>\n";
    }
    html << "</table></div>\n";

    for (const RowPage& r : page.rows) {
      const StageRow& row = *r.row;
      const StageView& v = r.view;
      const std::string id = anchor(effect, row.stage);
      html << "<section class=\"stage " << escape(r.verdict) << "\" id=\"" << escape(id) << "\" data-effect=\""
           << escape(effect) << "\" data-stage=\"" << escape(row.stage) << "\" data-verdict=\"" << escape(r.verdict)
           << "\">\n<h3><a href=\"#" << escape(id) << "\">" << escape(effect) << " · " << escape(row.stage) << "</a> "
           << verdictBadge(r.verdict) << " <span class=\"small\">";
      if (row.level >= 0) html << "level " << row.level << ", ";
      if (v.missing.empty()) html << "grid " << gridText(v.gridW, v.gridH);
      if (row.scale > 1) html << " (1/" << row.scale << " of full res)";
      html << " · <a href=\"#" << escape(anchor(effect, "summary")) << "\">summary</a></span></h3>\n";
      if (!v.missing.empty()) {
        html << "<p class=\"missing\">" << escape(v.missing) << "</p>\n";
      } else {
        html << "<div class=\"trio\">\n<figure><div class=\"wrap\">" << img(r.oracleImage, "oracle " + row.stage)
             << "</div><figcaption><b>oracle</b> (cpu_ref)</figcaption></figure>\n"
             << "<figure><div class=\"wrap\">" << img(r.portImage, "port " + row.stage)
             << "</div><figcaption><b>port</b> (" << escape(info.renderer) << ")</figcaption></figure>\n"
             << "<figure><div class=\"wrap\">";
        if (r.heatImage >= 0) {
          html << img(r.heatImage, "|Δ| " + row.stage);
          if (r.worst.shown && r.worst.gridX >= 0)
            html << "<span class=\"mark\" style=\"" << markStyle(r) << "\" title=\"worst pixel\"></span>";
        } else {
          html << "<p class=\"missing\" style=\"line-height:1.4;color:#ccc;padding:8px\">the two images differ in "
                  "size</p>";
        }
        html << "</div><figcaption><b>|Δ|</b> <span class=\"ramp\"></span> " << escape(v.deltaCaption) << "; "
             << r.heatCaption;
        if (r.worst.shown && r.worst.gridX >= 0) html << "; <span style=\"color:#0097a7\">■</span> the worst pixel";
        html << "</figcaption></figure>\n</div>\n<p class=\"small\">shown: " << escape(v.valueCaption) << "</p>\n";
      }
      html << "<div class=\"scroll\"><table class=\"figs\">\n<tr><th class=\"l\">check</th><th class=\"l\">rule</th>"
           << "<th class=\"l\">result</th><th>pixels</th><th>max|Δ|</th><th>over%</th><th>allowed%</th><th>rms</th>"
           << "<th>rms bound</th><th>threshold</th><th>worst (grid)</th><th class=\"l\">why</th></tr>\n"
           << checkTableRow("end to end", row.endToEnd) << checkTableRow("same input", row.sameInput)
           << "</table></div>\n";
      if (r.worst.shown) html << "<p>Worst pixel: " << worstText(r) << "</p>\n";
      html << "</section>\n";
    }
  }
  html << "<p class=\"small\">Scene credit: "
       << (info.credit.empty() ? std::string("(none given)") : escape(info.credit)) << "</p>\n</main>\n"
       << "<script>window.addEventListener('load',function(){var n=0,i,im=document.images;"
          "for(i=0;i<im.length;i++)if(im[i].complete&&im[i].naturalWidth>0)n++;"
          "document.body.dataset.loaded=String(n);document.body.dataset.images=String(im.length);"
          // Back to the #anchor once the images have their size.
          "var t=location.hash&&document.getElementById(decodeURIComponent(location.hash.slice(1)));"
          "if(t)t.scrollIntoView();});</script>\n"
       << "</body>\n</html>\n";
  writeTextFile(path, html.str());
}

}  // namespace mrr
