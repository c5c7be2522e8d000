#include "explore/layers.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "frontend/options.h"
#include "common/error.h"
#include "common/stages.h"
#include "compare/metrics/false_colour.h"
#include "compare/metrics/flip.h"
#include "cpu_ref/probe.h"

namespace mrr::explore {

namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int kShadowMapShown = 512;  // larger shadow maps are shown point-sampled down to this

ImageF fromBytes(const ImageU8& src) {
  ImageF out(src.width, src.height, 1, 0.0f);
  for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = src.data[i * static_cast<size_t>(src.channels)];
  return out;
}

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
// closure blue-grey, coarsest dark grey, fallback dark red, limit red.
constexpr uint8_t kReasonColours[][3] = {{0, 0, 0},     {255, 255, 255}, {0, 200, 230}, {255, 160, 40},
                                         {90, 110, 150}, {60, 60, 60},   {120, 20, 20}, {230, 40, 40}};

ColourMap colourMapOf(const LayerImage& l) {
  if (l.name.find(".normal") != std::string::npos) return ColourMap::Signed;
  if (l.name.find(".position") != std::string::npos) return ColourMap::Scaled;
  if (l.name == "shaded") return ColourMap::Srgb;
  return ColourMap::Plain;
}

}  // namespace

std::vector<std::string> layerNames(const FrameResult& f, bool hasReference) {
  std::vector<std::string> names;
  const Constants& c = f.constants;
  auto levelEnabled = [&](int l) { return !f.levels[static_cast<size_t>(l)].gbuffer.depth.empty(); };
  for (int l = 0; l < kLevelCount; ++l)
    if (levelEnabled(l))
      for (const char* ch : {"depth", "normal", "albedo", "position", "hit"})
        names.push_back(partName(Part::GBuffer, l) + "." + ch);
  if (!f.shadowMap.depth.empty()) names.push_back(partName(Part::ShadowMap));
  if (!f.shadowLit.empty()) names.push_back(partName(Part::ShadowTest));
  if (!f.edges.combined.empty()) {
    const std::string e = partName(Part::Edges);
    for (const char* kind : {"normal", "depth", "background"}) names.push_back(e + "." + kind);
    if (!f.edges.shadow.empty()) names.push_back(e + ".shadow");
    names.push_back(e);
  }
  if (!f.tileRates.empty()) names.push_back(partName(Part::TileRates));
  if (!f.eccentricity.empty()) names.push_back(partName(Part::Eccentricity));  // SPEC §13
  if (!f.motion.empty()) names.push_back(partName(Part::Motion));
  if (!f.levelLimit.empty()) names.push_back(partName(Part::LevelLimit));
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelResult& lr = f.levels[static_cast<size_t>(l)];
    const size_t li = static_cast<size_t>(l);
    if (!lr.masks.mask.empty()) names.push_back(partName(Part::Mask, l));
    if (!lr.marks.empty()) names.push_back(partName(Part::Marks, l));
    // SPEC §12.3's arms (mrr, mrr-effect): the mask from edges alone, the footprint, the marks, and why
    const MethodInfo& method = methodInfo(c.mode);
    const bool arms = !f.edges.combined.empty() && method.blurredMasks() && c.levels[li].enabled && !lr.masks.stencil.empty();
    if (arms && l != c.coarsestEnabled && method.masks == MaskBuilder::EffectEdges) {
      names.push_back(partName(Part::Mask, l) + ".geometry");
      names.push_back(partName(Part::Mask, l) + ".footprint");
      if (method.aPosteriori && c.effectMask.posterior > 0.0f && l >= c.effectMask.posteriorFinest) names.push_back(partName(Part::Mask, l) + ".marks");
    }
    if (arms) names.push_back(partName(Part::Mask, l) + ".why");
    if (!lr.masks.alpha.empty()) names.push_back(partName(Part::Alpha, l));
    if (!lr.masks.stencil.empty()) names.push_back(partName(Part::Stencil, l));
    if (!lr.raw.empty() && c.levels[li].shaded) names.push_back(partName(Part::Raw, l));
    if (!lr.sub.empty() && c.levels[li].shaded) names.push_back(partName(Part::Sub, l));
  }
  for (int l = kLevelCount - 1; l >= 0; --l) {  // the blend runs coarse to fine
    const size_t li = static_cast<size_t>(l);
    if (!f.blend.upsampled[li].empty()) names.push_back(partName(Part::Upsample, l));
    if (!f.blend.alpha[li].empty()) names.push_back(partName(Part::BlendAlpha, l));
    if (!f.blend.composite[li].empty()) names.push_back(partName(Part::Composite, l));
  }
  if (!f.blend.levelMap.empty()) names.push_back(partName(Part::LevelMap));
  names.push_back(partName(Part::Final));
  if (!f.shaded.empty()) names.push_back(partName(Part::Shaded));
  if (hasReference) names.insert(names.end(), {"difference", "flip"});
  return names;
}

namespace {

// A 0/1 image, white and black.
void binaryLayer(const ImageU8& img, const std::string& caption, LayerImage& out) {
  out.kind = LayerKind::Binary;
  out.values = fromBytes(img);
  out.channels = {"value"};
  out.caption = caption + ": 1 white, 0 black";
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
    binaryLayer(g.hit, "hit (geometry)", out);
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
  const std::vector<std::string> tokens = split(name, '.');
  int level = -1;
  if (partInfo(part).perLevel) {
    require(tokens.size() >= 2 && tokens[1].size() == 2 && tokens[1][0] == 'L' && tokens[1][1] >= '0' &&
                tokens[1][1] < '0' + kLevelCount,
            "no layer " + name);
    level = tokens[1][1] - '0';
    // the blend's images are on the W×H grid; the other per-level parts on their level's
    const bool fullRes = part == Part::Upsample || part == Part::BlendAlpha || part == Part::Composite;
    out.scale = fullRes ? 1 : f.constants.levels[static_cast<size_t>(level)].scale;
  }
  out.what = std::string(partInfo(part).what);
  const size_t li = static_cast<size_t>(std::max(level, 0));
  const LevelResult& lr = f.levels[li];
  const auto binary = [&](const ImageU8& img, const std::string& caption) { binaryLayer(img, caption, out); };
  const auto effect = [&](const ImageF& img, const std::string& caption) {
    out.kind = LayerKind::Effect;
    out.values = img;
    out.channels = img.channels == 3 ? std::vector<std::string>{"R", "G", "B"} : std::vector<std::string>{"value"};
    out.caption = caption + (img.channels == 3 ? " (RGB)" : "") + ", clamped to [0, 1]: 0 black, 1 white";
  };
  switch (part) {
    case Part::GBuffer: gbufferLayer(lr.gbuffer, tokens.size() == 3 ? tokens[2] : "", name, out); break;
    case Part::ShadowMap: shadowMapLayer(f.shadowMap, out); break;
    case Part::ShadowTest: binary(f.shadowLit, "the one-tap shadow test (1 = lit)"); break;
    case Part::Edges: {
      const std::string kind = tokens.size() == 2 ? tokens[1] : "E";
      const EdgeImages& e = f.edges;
      const ImageU8* img = kind == "normal"       ? &e.normal
                           : kind == "depth"      ? &e.depth
                           : kind == "background" ? &e.background
                           : kind == "shadow"     ? &e.shadow
                           : kind == "E"          ? &e.combined
                                                  : nullptr;
      require(img != nullptr && !img->empty(), "no layer " + name);
      binary(*img, kind == "E" ? "the edge image E, the OR of the kinds" : kind + " edges");
      break;
    }
    case Part::TileRates:
      out.kind = LayerKind::Levels;
      out.values = fromBytes(f.tileRates);
      out.scale = kTileSize;
      out.channels = {"rate"};
      out.lo = 0.0f;
      out.hi = 3.0f;
      out.caption = "each 16x16 tile's rate: 0 = 1x1, 1 = 2x2, 2 = 4x4";
      break;
    case Part::Eccentricity:
    case Part::Motion: {  // SPEC §13
      const bool ecc = part == Part::Eccentricity;
      const ImageF& img = ecc ? f.eccentricity : f.motion;
      require(!img.empty(), "no layer " + name);
      out.kind = LayerKind::Scalar;
      out.values = crop(img, f.constants.width, f.constants.height);
      for (float& v : out.values.data) v = std::min(v, ecc ? 30.0f : 16.0f);
      out.channels = {ecc ? "e" : "v"};
      out.lo = 0.0f;
      out.hi = ecc ? 30.0f : 16.0f;
      out.caption = ecc ? "eccentricity from the gaze, degrees, on the ramp over [0, 30]"
                        : "screen motion since the previous frame, pixels, on the ramp over [0, 16]";
      break;
    }
    case Part::LevelLimit: {
      require(!f.levelLimit.empty(), "no layer " + name);
      const ImageU8 cropped = crop(f.levelLimit, f.constants.width, f.constants.height);
      out.kind = LayerKind::Levels;
      out.values = ImageF(cropped.width, cropped.height, 1);
      for (int y = 0; y < cropped.height; ++y)
        for (int x = 0; x < cropped.width; ++x) out.values.at(x, y) = static_cast<float>(cropped.at(x, y, 2));
      out.channels = {"limit"};
      out.lo = 0.0f;
      out.hi = 3.0f;
      out.caption = "the level limit l_min: the finest level the eye and motion leave (masks below it cleared)";
      break;
    }
    case Part::Mask: {
      const std::string sub = tokens.size() == 3 ? tokens[2] : "";
      if (sub.empty()) {
        binary(lr.masks.mask, methodInfo(f.constants.mode).masks == MaskBuilder::EffectEdges
                                 ? "the mask M' the blur reads (widened, with any marks)"
                                 : "the max-pooled edge mask M");
        break;
      }
      const CoverageArms arms = coverageArms(f);  // SPEC §12.3
      require(arms.active, "no layer " + name);
      if (sub == "geometry") {
        binary(arms.stages.geometry[li], "the mask from edges alone (mrr's M, before the effect's widening)");
      } else if (sub == "marks") {
        require(!arms.marks[li].empty(), "no layer " + name);
        binary(arms.marks[li], "the a-posteriori marks: the next coarser result varies by more than tau over 3x3");
      } else if (sub == "footprint") {
        require(!arms.stages.footprintMax[li].empty(), "no layer " + name);
        out.kind = LayerKind::Scalar;
        out.values = arms.stages.footprintMax[li];
        out.channels = {"F"};
        finiteRange(out.values, out.lo, out.hi);
        out.caption = "the effect's footprint F at edge pixels (max over each level pixel's block), full-res pixels, on "
                      "the ramp; its reach K = min(cap, round(F / s)) level pixels";
      } else if (sub == "why") {
        const int w = lr.masks.stencil.width, h = lr.masks.stencil.height;
        out.kind = LayerKind::Reason;
        out.values = ImageF(w, h, 1);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x)
            out.values.at(x, y) = static_cast<float>(coverageReason(arms, f, level, x, y));
        out.channels = {"why"};
        out.lo = 0.0f;
        out.hi = static_cast<float>(Coverage::Limit);
        out.caption = "why this level covers each pixel (docs/spec.md 12.3): white an edge (geometry), cyan the "
                      "effect's footprint, orange the a-posteriori marks, blue-grey the closure (a finer level "
                      "shades inside), dark grey the coarsest level; not covered: black nothing, red the level limit";
      } else {
        throw MrrError("no layer " + name);
      }
      break;
    }
    case Part::Marks:  // SPEC §12.2: the frame's own marks (the port's, on a port frame)
      require(!lr.marks.empty(), "no layer " + name);
      binary(lr.marks, "the a-posteriori marks this frame refined with (after the level limit)");
      break;
    case Part::Stencil: binary(lr.masks.stencil, "the stencil S: shaded at this level"); break;
    case Part::Alpha:
      out.kind = LayerKind::Scalar;
      out.values = lr.masks.alpha;
      out.channels = {"a"};
      out.caption = "the blurred mask a on the ramp over [0, 1]";
      break;
    case Part::Raw: {
      ImageF raw = lr.raw;  // not evaluated where S = 0: shown grey
      const size_t ch = static_cast<size_t>(raw.channels);
      for (size_t p = 0; p < lr.masks.stencil.data.size() && p * ch < raw.data.size(); ++p)
        if (!lr.masks.stencil.data[p])
          for (size_t k = 0; k < ch; ++k) raw.data[p * ch + k] = kNaN;
      effect(raw, "the effect where S = 1 (grey: not evaluated)");
      break;
    }
    case Part::Sub: effect(lr.sub, "the sub-image c after the bilateral blur"); break;
    case Part::Upsample: effect(f.blend.upsampled[li], "the masked-bilinear upsampled c^"); break;
    case Part::Composite: effect(f.blend.composite[li], "the composite c' after blending this level"); break;
    case Part::BlendAlpha:
      out.kind = LayerKind::Scalar;
      out.values = f.blend.alpha[li];
      out.channels = {"alpha"};
      out.caption = "alpha = min(a^ w, 1) on the ramp over [0, 1]";
      break;
    case Part::LevelMap:
      out.kind = LayerKind::Levels;
      out.values = fromBytes(f.blend.levelMap);
      out.channels = {"level"};
      out.lo = 0.0f;
      out.hi = 3.0f;
      out.caption = "the finest level with alpha > 0: one ramp colour per level, 0 (full) dark to 3 (1/8) bright";
      break;
    case Part::Final: effect(f.final(), "the effect buffer"); break;
    case Part::Temporal:  // SPEC §14: the share of the previous frame each pixel kept
      out.kind = LayerKind::Effect;
      out.values = f.temporal.weight;
      out.channels = {"lambda_p"};
      out.caption = "SPEC 14: lambda_p, the share of the previous frame's result the pixel kept (0: none)";
      break;
    case Part::Shaded:
      out.kind = LayerKind::Colour;
      out.values = f.shaded;
      out.channels = {"R", "G", "B"};
      out.caption = "the shaded image, linear RGB shown sRGB-encoded";
      break;
  }
  require(!out.values.empty(), "layer " + name + " is empty in this frame");
  if (out.kind == LayerKind::Binary || out.kind == LayerKind::Effect || part == Part::Alpha ||
      part == Part::BlendAlpha) {
    out.lo = 0.0f;
    out.hi = 1.0f;
  }
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
    const float first = v.data[p * ch];
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
    for (const float v : l.values.data) ones += v != 0.0f;
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
