#include "explore/layers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "frontend/options.h"
#include "common/error.h"
#include "common/stage_images.h"
#include "common/stages.h"
#include "compare/metrics/false_colour.h"
#include "compare/metrics/flip.h"
#include "cpu_ref/probe.h"

namespace mrr::explore {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int kShadowMapShown = 512;  // larger shadow maps are shown point-sampled down to this

// `src` with background pixels (hit = 0) as NaN: the page shows them as "background".
ImageF maskedByHit(const ImageF& src, const ImageU8& hit) {
  ImageF out = src;
  const size_t ch = static_cast<size_t>(src.channels);
  for (size_t p = 0; p < hit.data.size() && p * ch < out.data.size(); ++p)
    if (!hit.data[p])
      for (size_t c = 0; c < ch; ++c) out.data[p * ch + c] = kNaN;
  return out;
}

void finiteRange(const ImageF& v, float& lo, float& hi) {
  lo = std::numeric_limits<float>::max();
  hi = std::numeric_limits<float>::lowest();
  for (const float x : v.data)
    if (std::isfinite(x)) lo = std::min(lo, x), hi = std::max(hi, x);
  if (lo > hi) lo = hi = 0.0f;
}

uint8_t byteOf(float v) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(v * 255.0f));
}

float srgbEncode(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

const char* kindName(LayerKind k) {
  switch (k) {
    case LayerKind::Binary: return "binary";
    case LayerKind::Effect: return "effect";
    case LayerKind::Scalar: return "scalar";
    case LayerKind::Colour: return "colour";
    case LayerKind::Levels: return "levels";
    case LayerKind::Flip: return "flip";
    case LayerKind::Reason: return "reason";
  }
  return "?";
}

// How a Colour layer maps its values: 0.5 + 0.5 v (normals), v / hi (positions), sRGB (shaded).
enum class ColourMap { Signed, Scaled, Plain, Srgb };
// SPEC §12.3's reasons, by Coverage: none black, geometry white, effect cyan, marks orange,
// closure blue-grey, coarsest dark grey, fallback dark red, limit red, trim (SPEC §12.5) purple.
constexpr uint8_t kReasonColours[][3] = {{0, 0, 0},     {255, 255, 255}, {0, 200, 230}, {255, 160, 40}, {90, 110, 150},
                                         {60, 60, 60},  {120, 20, 20},   {230, 40, 40}, {150, 60, 200}};

ColourMap colourMapOf(const LayerImage& l) {
  if (l.name.find(".normal") != std::string::npos) return ColourMap::Signed;
  if (l.name.find(".position") != std::string::npos) return ColourMap::Scaled;
  Part part{};
  if (partOf(l.name, part) && partInfo(part).view.display == Display::Colour) return ColourMap::Srgb;  // linear RGB
  return ColourMap::Plain;
}

}  // namespace

namespace {

// SPEC §12.3's arms of level ℓ's mask (mrr, mrr-effect): the mask from edges alone, the footprint
// and the marks (mrr-effect, below the coarsest level), and why the level covers each pixel.
void maskArms(const FrameResult& f, int l, std::vector<std::string>& names) {
  const Constants& c = f.constants;
  const size_t li = static_cast<size_t>(l);
  const MethodInfo& method = methodInfo(c.mode);
  const bool arms = !f.edges.combined.empty() && method.blurredMasks() && c.levels[li].enabled &&
                    !f.levels[li].masks.stencil.empty();
  const std::string mask = partName(Part::Mask, l);
  if (arms && l != c.coarsestEnabled && method.masks == MaskBuilder::EffectEdges) {
    names.push_back(mask + ".geometry");
    names.push_back(mask + ".footprint");
    if (method.aPosteriori && c.effectMask.posterior > 0.0f && l >= c.effectMask.posteriorFinest)
      names.push_back(mask + ".marks");
  }
  if (arms) names.push_back(mask + ".why");
}

// A part's layers: one, or the multi-channel parts' several (the G-buffer's channel groups, each
// edge kind and E), and after a mask its arms.
void partLayers(const FrameResult& f, const PartRef& ref, std::vector<std::string>& names) {
  const std::string name = ref.name();
  switch (partInfo(ref.part).view.display) {
    case Display::GBuffer:
      for (const char* group : {"depth", "normal", "albedo", "position", "hit"}) names.push_back(name + "." + group);
      break;
    case Display::Edges:  // the kinds in the part's channel order, E last; shadow where the frame has it
      for (const std::string& kind : partChannels(ref.part))
        if (kind != "E" && (kind != "shadow" || !f.edges.shadow.empty())) names.push_back(name + "." + kind);
      names.push_back(name);
      break;
    default: names.push_back(name);
  }
  if (ref.part == Part::Mask) maskArms(f, ref.level, names);
}

}  // namespace

std::vector<std::string> layerNames(const FrameResult& f, bool hasReference) {
  // The parts the frame holds, in the table's order as the stages EXR (heldParts), but in a run of
  // per-level rows the blend's (step 5) come after every level's masks and sub-images, coarse to
  // fine: the order the blend runs in.
  std::vector<std::string> names;
  const Constants& c = f.constants;
  for (size_t i = 0; i < std::size(kParts);) {
    if (!kParts[i].perLevel) {
      if (holdsPart(f, kParts[i].part)) partLayers(f, {kParts[i].part}, names);
      ++i;
      continue;
    }
    size_t end = i;
    while (end < std::size(kParts) && kParts[end].perLevel) ++end;
    for (const bool blend : {false, true})
      for (int k = 0; k < kLevelCount; ++k) {
        const int l = blend ? kLevelCount - 1 - k : k;
        if (!c.levels[static_cast<size_t>(l)].enabled) continue;
        for (size_t r = i; r < end; ++r)
          if ((kParts[r].step == 5) == blend && holdsPart(f, kParts[r].part, l))
            partLayers(f, {kParts[r].part, l}, names);
      }
    i = end;
  }
  if (hasReference) names.insert(names.end(), {"difference", "flip"});
  return names;
}

namespace {

// A 0/1 image, white and black.
void binaryLayer(const ImageF& img, const std::string& caption, LayerImage& out) {
  out.kind = LayerKind::Binary;
  out.values = img;
  out.channels = {"value"};
  out.lo = 0.0f;
  out.hi = 1.0f;
  out.caption = caption + ": 1 white, 0 black";
}

// A part as its row shows it (common/stages.h PartView), read by the row's accessor.
void partLayer(const FrameResult& f, Part part, int level, LayerImage& out) {
  const PartView& shown = partInfo(part).view;
  out.values = readPart(f, part, level);
  if (out.values.empty()) return;
  out.channels = partChannels(part, out.values);
  out.channel = shown.channel;
  out.caption = viewCaption(part, out.values.channels);
  out.lo = 0.0f;
  out.hi = 1.0f;
  switch (shown.display) {
    case Display::Binary: out.kind = LayerKind::Binary; break;
    case Display::Levels:
      out.kind = LayerKind::Levels;
      out.hi = static_cast<float>(kLevelCount - 1);
      break;
    case Display::Scalar:
      out.kind = LayerKind::Scalar;
      out.lo = shown.lo;
      out.hi = shown.hi;
      if (!(out.hi > out.lo)) finiteRange(out.values, out.lo, out.hi);
      break;
    case Display::Colour: out.kind = LayerKind::Colour; break;
    default: out.kind = LayerKind::Effect; break;
  }
  if (shown.shadedOnly) {  // never evaluated where S_ℓ = 0: shown grey
    const ImageF stencil = readPart(f, Part::Stencil, level);
    const size_t ch = static_cast<size_t>(out.values.channels);
    if (stencil.pixelCount() == out.values.pixelCount()) {
      for (size_t p = 0; p < stencil.data.size(); ++p)
        if (stencil.data[p] == 0.0f)
          for (size_t k = 0; k < ch; ++k) out.values.data[p * ch + k] = kNaN;
      out.caption += "; grey where S_ℓ = 0 (not evaluated)";
    }
  }
}

// |frame - full resolution|, max over channels, scaled by `gain` on the ramp.
LayerImage differenceLayer(const FrameResult& f, const FrameResult& reference, float gain) {
  LayerImage out;
  out.name = "difference";
  const ImageF& a = f.final();
  const ImageF& b = reference.final();
  require(a.width == b.width && a.height == b.height && a.channels == b.channels,
          "difference: the frame and the full-resolution frame differ in size");
  out.values = ImageF(a.width, a.height, 1, 0.0f);
  const size_t ch = static_cast<size_t>(a.channels);
  for (size_t p = 0; p < out.values.data.size(); ++p) {
    float d = 0.0f;
    for (size_t k = 0; k < ch; ++k) d = std::max(d, std::fabs(a.data[p * ch + k] - b.data[p * ch + k]));
    out.values.data[p] = d;
  }
  out.channels = {"abs_diff"};
  out.kind = LayerKind::Scalar;
  out.lo = 0.0f;
  out.hi = 1.0f / std::max(gain, 1e-6f);
  char text[160];
  std::snprintf(text, sizeof text, "|this frame - full resolution| x %g on the ramp (full scale = %g)", gain, out.hi);
  out.caption = text;
  out.what = "the difference from the full-resolution frame (mode full, same samples)";
  return out;
}

// LDR-FLIP of this frame's effect buffer against the full-resolution one's (the effect as grey,
// clamped to [0, 1], at the default viewing distance), as the bench and `render --reference` measure.
LayerImage flipLayer(const FrameResult& f, const FrameResult& reference) {
  LayerImage out;
  out.name = "flip";
  const ImageF& a = f.final();
  const ImageF& b = reference.final();
  require(a.width == b.width && a.height == b.height && a.channels == b.channels,
          "flip: the frame and the full-resolution frame differ in size");
  FlipResult r = flip(b, a);
  out.values = std::move(r.errorMap);
  out.channels = {"flip"};
  out.kind = LayerKind::Flip;
  out.lo = 0.0f;
  out.hi = 1.0f;
  char text[200];
  std::snprintf(text, sizeof text,
                "LDR-FLIP of this frame against full resolution (the effect as grey, %.0f pixels per degree), "
                "magma: 0 black to 1 pale yellow; mean %.4g, max %.3g",
                kFlipDefaultPpd, r.stats.mean, r.stats.max);
  out.caption = text;
  out.what = "the perceptual difference (LDR-FLIP) from the full-resolution frame (mode full, same samples)";
  return out;
}

// One channel of a level's G-buffer: hit, depth, normal, albedo or position.
void gbufferLayer(const GBuffer& g, const std::string& channel, const std::string& name, LayerImage& out) {
  if (channel == "hit") {
    binaryLayer(toFloat(g.hit), "hit (geometry)", out);
  } else if (channel == "depth") {
    out.kind = LayerKind::Scalar;
    out.values = maskedByHit(g.depth, g.hit);
    out.channels = {"z"};
    finiteRange(out.values, out.lo, out.hi);
    out.caption = "linear view depth z on the ramp, near to far; background grey";
  } else if (channel == "normal" || channel == "albedo" || channel == "position") {
    out.kind = LayerKind::Colour;
    out.values = maskedByHit(channel == "normal" ? g.normal : channel == "albedo" ? g.albedo : g.position, g.hit);
    out.channels = {"x", "y", "z"};
    if (channel == "albedo") out.channels = {"R", "G", "B"};
    if (channel == "position") {
      out.lo = 0.0f;
      out.hi = 1.0f;
      for (const float v : out.values.data)
        if (std::isfinite(v)) out.hi = std::max(out.hi, std::fabs(v));
    }
    out.caption = channel == "normal"   ? "view-space normal as 0.5 + 0.5 n (RGB); background grey"
                  : channel == "albedo" ? "base colour (linear RGB); background grey"
                                        : "view-space position as 0.5 + 0.5 P / max|P| (RGB); background grey";
  } else {
    throw MrrError("no layer " + name);
  }
}

// The light's shadow map, every factor-th texel so that it is shown at most kShadowMapShown wide.
void shadowMapLayer(const ShadowMap& m, LayerImage& out) {
  const int factor = std::max(1, (m.depth.width + kShadowMapShown - 1) / kShadowMapShown);
  out.values = ImageF((m.depth.width + factor - 1) / factor, (m.depth.height + factor - 1) / factor, 1, 0.0f);
  for (int y = 0; y < out.values.height; ++y)
    for (int x = 0; x < out.values.width; ++x) {
      const float d = m.depth.at(x * factor, y * factor);
      out.values.at(x, y) = d == ShadowMap::kNoBlocker || !std::isfinite(d) ? kNaN : d;
    }
  out.kind = LayerKind::Scalar;
  out.scale = 0;  // the light's grid, not the screen's
  out.channels = {"distance"};
  finiteRange(out.values, out.lo, out.hi);
  out.caption = "distance from the light plane on the ramp; no blocker grey" +
                (factor > 1 ? "; shown every " + std::to_string(factor) + "th texel" : std::string());
}

// SPEC §12.3's arms of level ℓ's mask: "geometry", "footprint", "marks" or "why".
void maskArmLayer(const FrameResult& f, int level, const std::string& arm, const std::string& name, LayerImage& out) {
  const size_t li = static_cast<size_t>(level);
  const CoverageArms arms = coverageArms(f);
  require(arms.active, "no layer " + name);
  if (arm == "geometry") {
    binaryLayer(toFloat(arms.stages.geometry[li]), "the mask from edges alone (mrr's M, before the effect's widening)",
                out);
  } else if (arm == "marks") {
    require(!arms.marks[li].empty(), "no layer " + name);
    binaryLayer(toFloat(arms.marks[li]),
                "the a-posteriori marks: the next coarser result varies by more than tau over 3x3", out);
  } else if (arm == "footprint") {
    require(!arms.stages.footprintMax[li].empty(), "no layer " + name);
    out.kind = LayerKind::Scalar;
    out.values = arms.stages.footprintMax[li];
    out.channels = {"F"};
    finiteRange(out.values, out.lo, out.hi);
    out.caption = "the effect's footprint F at edge pixels (max over each level pixel's block), full-res pixels, on "
                  "the ramp; its reach K = min(cap, round(F / s)) level pixels";
  } else if (arm == "why") {
    const ImageU8& stencil = f.levels[li].masks.stencil;
    out.kind = LayerKind::Reason;
    out.values = ImageF(stencil.width, stencil.height, 1);
    for (int y = 0; y < stencil.height; ++y)
      for (int x = 0; x < stencil.width; ++x)
        out.values.at(x, y) = static_cast<float>(coverageReason(arms, f, level, x, y));
    out.channels = {"why"};
    out.lo = 0.0f;
    out.hi = static_cast<float>(Coverage::Trim);
    out.caption = "why this level covers each pixel (docs/spec.md 12.3): white an edge (geometry), cyan the "
                  "effect's footprint, orange the a-posteriori marks, blue-grey the closure (a finer level "
                  "shades inside), dark grey the coarsest level; not covered: black nothing, red the level limit, "
                  "purple the trim (docs/spec.md 12.5: the blend does not read it)";
  } else {
    throw MrrError("no layer " + name);
  }
}

}  // namespace

LayerImage makeLayer(const FrameResult& f, const std::string& name, const FrameResult* reference, float gain) {
  const std::vector<std::string> layers = layerNames(f, reference != nullptr);
  require(std::find(layers.begin(), layers.end(), name) != layers.end(), "no layer " + name + " in this frame");
  LayerImage out;
  out.name = name;
  if (name == "difference") return differenceLayer(f, *reference, gain);
  if (name == "flip") return flipLayer(f, *reference);
  Part part{};
  require(partOf(name, part), "no layer " + name);
  const PartInfo& row = partInfo(part);
  const std::vector<std::string> tokens = split(name, '.');
  int level = -1;
  if (row.perLevel) {
    require(tokens.size() >= 2 && tokens[1].size() == 2 && tokens[1][0] == 'L' && tokens[1][1] >= '0' &&
                tokens[1][1] < '0' + kLevelCount,
            "no layer " + name);
    level = tokens[1][1] - '0';
  }
  switch (row.grid) {  // full-res pixels a texel
    case Grid::Level: out.scale = f.constants.levels[static_cast<size_t>(std::max(level, 0))].scale; break;
    case Grid::Screen: out.scale = 1; break;
    case Grid::Tiles: out.scale = kTileSize; break;
    case Grid::Light: out.scale = 0; break;  // the light's grid, not the screen's
  }
  out.what = std::string(row.what);
  // A G-buffer channel group, an edge kind or a mask's arm.
  const std::string sub = tokens.size() == (row.perLevel ? 3u : 2u) ? tokens.back() : "";
  const size_t li = static_cast<size_t>(std::max(level, 0));
  switch (row.view.display) {  // the multi-channel parts' own layers, and the masks' arms
    case Display::GBuffer: gbufferLayer(f.levels[li].gbuffer, sub, name, out); break;
    case Display::ShadowMap: shadowMapLayer(f.shadowMap, out); break;
    case Display::Edges: {
      const ImageF edges = readPart(f, part);
      const std::vector<std::string> kinds = partChannels(part, edges);
      const std::string kind = sub.empty() ? "E" : sub;
      const auto at = std::find(kinds.begin(), kinds.end(), kind);
      require(at != kinds.end(), "no layer " + name);
      binaryLayer(imageChannel(edges, static_cast<int>(at - kinds.begin())),
                  kind == "E" ? viewCaption(part, 1) : kind + " edges", out);
      break;
    }
    default:
      if (part == Part::Mask && !sub.empty())
        maskArmLayer(f, level, sub, name, out);
      else
        partLayer(f, part, level, out);
  }
  require(!out.values.empty(), "layer " + name + " is empty in this frame");
  return out;
}

ImageU8 colourise(const LayerImage& l) {
  const ImageF& v = l.values;
  ImageU8 out(v.width, v.height, 3, 0);
  const size_t ch = static_cast<size_t>(v.channels);
  const ColourMap map = colourMapOf(l);
  const float span = l.hi > l.lo ? l.hi - l.lo : 1.0f;
  for (size_t p = 0; p < v.pixelCount(); ++p) {
    uint8_t* rgb = &out.data[p * 3];
    const float first = v.data[p * ch + std::min(static_cast<size_t>(l.channel), ch - 1)];  // the channel shown
    if (std::isnan(first)) {  // background, not evaluated, no blocker
      rgb[0] = rgb[1] = rgb[2] = 72;
      continue;
    }
    switch (l.kind) {
      case LayerKind::Binary: rgb[0] = rgb[1] = rgb[2] = first != 0.0f ? 255 : 0; break;
      case LayerKind::Effect:
        for (size_t c = 0; c < 3; ++c) rgb[c] = byteOf(v.data[p * ch + std::min(c, ch - 1)]);
        break;
      case LayerKind::Scalar: rampColour((first - l.lo) / span, rgb); break;
      case LayerKind::Levels: rampColour(0.15 + 0.8 * first / 3.0, rgb); break;
      case LayerKind::Reason: {
        const size_t k = std::min<size_t>(static_cast<size_t>(std::max(first, 0.0f)), std::size(kReasonColours) - 1);
        for (size_t c = 0; c < 3; ++c) rgb[c] = kReasonColours[k][c];
        break;
      }
      case LayerKind::Flip: flipMagma(first, rgb); break;
      case LayerKind::Colour:
        for (size_t c = 0; c < 3; ++c) {
          const float x = v.data[p * ch + std::min(c, ch - 1)];
          float shown = x;
          if (map == ColourMap::Signed) shown = 0.5f + 0.5f * x;
          if (map == ColourMap::Scaled) shown = 0.5f + 0.5f * x / (l.hi > 0.0f ? l.hi : 1.0f);
          if (map == ColourMap::Srgb) shown = srgbEncode(x);
          rgb[c] = byteOf(shown);
        }
        break;
    }
  }
  return out;
}

ImageF layerDifference(const LayerImage& a, const LayerImage& b, float* largest) {
  *largest = 0.0f;
  if (a.values.width != b.values.width || a.values.height != b.values.height || a.values.channels != b.values.channels)
    return {};
  ImageF out(a.values.width, a.values.height, 1, 0.0f);
  const size_t ch = static_cast<size_t>(a.values.channels);
  for (size_t p = 0; p < out.data.size(); ++p) {
    float worst = 0.0f;
    for (size_t c = 0; c < ch; ++c) {
      const float x = a.values.data[p * ch + c], y = b.values.data[p * ch + c];
      if (std::isnan(x) && std::isnan(y)) continue;  // both background
      const float d = std::fabs(x - y);
      worst = std::max(worst, std::isnan(d) ? std::numeric_limits<float>::infinity() : d);
    }
    out.data[p] = worst;
    if (std::isfinite(worst)) *largest = std::max(*largest, worst);
  }
  return out;
}

nlohmann::json layerMeta(const LayerImage& l) {
  nlohmann::json j = {{"name", l.name},
                      {"kind", kindName(l.kind)},
                      {"width", l.values.width},
                      {"height", l.values.height},
                      {"scale", l.scale},
                      {"channels", l.channels},
                      {"lo", l.lo},
                      {"hi", l.hi},
                      {"caption", l.caption},
                      {"what", l.what},
                      {"ramp", l.kind == LayerKind::Flip ? flipMagmaGradient() : rampGradient()}};
  if (l.kind == LayerKind::Flip) j["mean"] = flipStats(l.values).mean;
  if (l.kind == LayerKind::Binary) {
    long long ones = 0;
    const size_t ch = static_cast<size_t>(std::max(l.values.channels, 1));
    for (size_t p = 0; p < l.values.pixelCount(); ++p)
      ones += l.values.data[p * ch + static_cast<size_t>(l.channel)] != 0.0f;
    j["ones"] = ones;
  }
  if (l.kind == LayerKind::Levels) {
    nlohmann::json swatches = nlohmann::json::array();
    for (int k = 0; k <= 3; ++k) {
      uint8_t rgb[3];
      rampColour(0.15 + 0.8 * k / 3.0, rgb);
      swatches.push_back("rgb(" + std::to_string(rgb[0]) + "," + std::to_string(rgb[1]) + "," + std::to_string(rgb[2]) + ")");
    }
    j["swatches"] = swatches;
  }
  if (l.kind == LayerKind::Reason) {  // SPEC §12.3: a swatch and a name per reason
    nlohmann::json swatches = nlohmann::json::array(), names = nlohmann::json::array();
    for (size_t k = 0; k < std::size(kReasonColours); ++k) {
      const uint8_t* rgb = kReasonColours[k];
      swatches.push_back("rgb(" + std::to_string(rgb[0]) + "," + std::to_string(rgb[1]) + "," + std::to_string(rgb[2]) + ")");
      names.push_back(coverageName(static_cast<Coverage>(k)));
    }
    j["swatches"] = swatches;
    j["names"] = names;
  }
  return j;
}

nlohmann::json layerValueAt(const LayerImage& l, int x, int y) {
  if (l.scale <= 0) return {{"layer", l.name}, {"values", nullptr}, {"note", "not on the screen's grid"}};
  const int gx = x / l.scale, gy = y / l.scale;
  nlohmann::json values = nlohmann::json::object();
  if (l.values.contains(gx, gy))
    for (size_t c = 0; c < l.channels.size(); ++c) {
      const float v = l.values.at(gx, gy, static_cast<int>(c));
      values[l.channels[c]] = std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    }
  return {{"layer", l.name}, {"pixel", {x, y}}, {"grid_pixel", {gx, gy}}, {"values", values}};
}

}  // namespace mrr::explore
