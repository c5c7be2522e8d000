#include "common/stage_images.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <type_traits>

#include "common/error.h"

namespace mrr {

namespace {

// ---- Layouts ------------------------------------------------------------------------------

bool validLevel(int level) { return level >= 0 && level < kLevelCount; }

size_t levelIndex(int level, const char* part) {
  require(validLevel(level), std::string("part ") + part + ": level " + std::to_string(level) + " is not in [0, " +
                                 std::to_string(kLevelCount - 1) + "]");
  return static_cast<size_t>(level);
}

// A byte image (0/1 flags, level indices, tile rates) from its floats, rounded.
ImageU8 toBytes(const ImageF& image) {
  ImageU8 out(image.width, image.height, image.channels);
  for (size_t i = 0; i < image.data.size(); ++i)
    out.data[i] = static_cast<uint8_t>(std::lround(std::clamp(image.data[i], 0.0f, 255.0f)));
  return out;
}

// A padded full-res grid (docs/spec.md §0) as its EXR part: the top-left W×H, as floats.
ImageF screen(const ImageF& padded, const Constants& c) {
  return padded.empty() ? ImageF() : crop(padded, c.width, c.height);
}
ImageF screen(const ImageU8& padded, const Constants& c) {
  return padded.empty() ? ImageF() : toFloat(crop(padded, c.width, c.height));
}

// The inverse: `image` written over the top-left of the padded grid, which keeps the rest; a grid
// the frame lacks (or of other channels) is made, zero-filled, at the padded size.
template <class T>
void overwrite(Image<T>& padded, const ImageF& image, const Constants& c) {
  if (padded.empty() || padded.channels != image.channels)
    padded =
        Image<T>(std::max(c.paddedWidth, image.width), std::max(c.paddedHeight, image.height), image.channels, T(0));
  for (int y = 0; y < image.height && y < padded.height; ++y)
    for (int x = 0; x < image.width && x < padded.width; ++x)
      for (int k = 0; k < image.channels; ++k) {
        const float v = image.at(x, y, k);
        if constexpr (std::is_same_v<T, float>)
          padded.at(x, y, k) = v;
        else
          padded.at(x, y, k) = static_cast<T>(std::lround(std::clamp(v, 0.0f, 255.0f)));
      }
}

// Channels [first, first + n) of `image`.
ImageF channels(const ImageF& image, int first, int n) {
  ImageF out(image.width, image.height, n);
  for (size_t p = 0; p < image.pixelCount(); ++p)
    for (int k = 0; k < n; ++k)
      out.data[p * static_cast<size_t>(n) + static_cast<size_t>(k)] =
          image.data[p * static_cast<size_t>(image.channels) + static_cast<size_t>(first + k)];
  return out;
}

// Writes channels of `from` into `image` from channel `first` on.
void putChannels(ImageF& image, int first, const ImageF& from) {
  for (size_t p = 0; p < image.pixelCount(); ++p)
    for (int k = 0; k < from.channels; ++k)
      image.data[p * static_cast<size_t>(image.channels) + static_cast<size_t>(first + k)] =
          from.data[p * static_cast<size_t>(from.channels) + static_cast<size_t>(k)];
}

void requireChannels(const ImageF& image, int n, const char* part) {
  require(image.channels == n, std::string("part ") + part + ": " + std::to_string(image.channels) +
                                   " channels, expected " + std::to_string(n));
}

// ---- One accessor per row -------------------------------------------------------------------
// A part held as an image of the frame, as is (float) or as bytes: these make its accessor.

template <auto Get>
ImageF readFloat(const FrameResult& f, int level) {
  const ImageF* image = Get(f, level);
  return image ? *image : ImageF();
}
template <auto Get>
ImageF readBytes(const FrameResult& f, int level) {
  const ImageU8* image = Get(f, level);
  return image && !image->empty() ? toFloat(*image) : ImageF();
}
template <auto Get>
bool holdsImage(const FrameResult& f, int level) {
  const auto* image = Get(f, level);
  return image && !image->empty();
}
template <auto Get>
auto* writable(FrameResult& f, int level) {
  const auto* image = Get(f, level);
  require(image != nullptr, "a per-level part at level " + std::to_string(level) + ", outside [0, " +
                                std::to_string(kLevelCount - 1) + "]");
  return const_cast<std::remove_cvref_t<decltype(*image)>*>(image);
}
template <auto Get>
void writeFloat(FrameResult& f, int level, const ImageF& image) {
  *writable<Get>(f, level) = image;
}
template <auto Get>
void writeBytes(FrameResult& f, int level, const ImageF& image) {
  *writable<Get>(f, level) = toBytes(image);
}
template <auto Get>
constexpr PartImageAccess floatImage() {
  return {holdsImage<Get>, readFloat<Get>, writeFloat<Get>, Get};
}
template <auto Get>
constexpr PartImageAccess byteImage() {
  return {holdsImage<Get>, readBytes<Get>, writeBytes<Get>, nullptr};
}
// The same for a padded full-res grid, cropped to W×H.
template <auto Get>
constexpr PartImageAccess screenImage() {
  return {
      holdsImage<Get>, [](const FrameResult& f, int level) { return screen(*Get(f, level), f.constants); },
      [](FrameResult& f, int level, const ImageF& image) { overwrite(*writable<Get>(f, level), image, f.constants); },
      nullptr};
}

// Where each image lies: null for a per-level part at a level outside [0, kLevelCount), which no
// frame holds and the writers refuse. The writers take the frame as const and cast (the frame is
// theirs to write): one getter serves both.
const ImageU8* marksOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.levels[static_cast<size_t>(l)].marks : nullptr;
}
const ImageU8* maskOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.levels[static_cast<size_t>(l)].masks.mask : nullptr;
}
const ImageF* alphaOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.levels[static_cast<size_t>(l)].masks.alpha : nullptr;
}
const ImageU8* stencilOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.levels[static_cast<size_t>(l)].masks.stencil : nullptr;
}
const ImageF* rawOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.levels[static_cast<size_t>(l)].raw : nullptr;
}
const ImageF* subOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.levels[static_cast<size_t>(l)].sub : nullptr;
}
const ImageF* upsampleOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.blend.upsampled[static_cast<size_t>(l)] : nullptr;
}
const ImageF* blendAlphaOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.blend.alpha[static_cast<size_t>(l)] : nullptr;
}
const ImageF* compositeOf(const FrameResult& f, int l) {
  return validLevel(l) ? &f.blend.composite[static_cast<size_t>(l)] : nullptr;
}
const ImageU8* shadowLitOf(const FrameResult& f, int) { return &f.shadowLit; }
const ImageF* eccentricityOf(const FrameResult& f, int) { return &f.eccentricity; }
const ImageF* motionOf(const FrameResult& f, int) { return &f.motion; }
const ImageU8* levelLimitOf(const FrameResult& f, int) { return &f.levelLimit; }
const ImageU8* tileRatesOf(const FrameResult& f, int) { return &f.tileRates; }
const ImageU8* levelMapOf(const FrameResult& f, int) { return &f.blend.levelMap; }
const ImageF* finalOf(const FrameResult& f, int) { return &f.blend.final; }
const ImageF* shadedOf(const FrameResult& f, int) { return &f.shaded; }

// The G-buffer's 11 channels: depth, P.xyz, N.xyz, albedo.RGB, hit.
constexpr int kGBufferChannels = 11;
ImageF readGBuffer(const FrameResult& f, int l) {
  if (!validLevel(l)) return {};
  const GBuffer& g = f.levels[static_cast<size_t>(l)].gbuffer;
  if (g.depth.empty()) return {};
  ImageF out(g.width, g.height, kGBufferChannels);
  putChannels(out, 0, g.depth);
  putChannels(out, 1, g.position);
  putChannels(out, 4, g.normal);
  putChannels(out, 7, g.albedo);
  putChannels(out, 10, toFloat(g.hit));
  return out;
}
void writeGBuffer(FrameResult& f, int l, const ImageF& image) {
  requireChannels(image, kGBufferChannels, "gbuffer");
  GBuffer& g = f.levels[levelIndex(l, "gbuffer")].gbuffer;
  g.width = image.width;
  g.height = image.height;
  g.depth = channels(image, 0, 1);
  g.position = channels(image, 1, 3);
  g.normal = channels(image, 4, 3);
  g.albedo = channels(image, 7, 3);
  g.hit = toBytes(channels(image, 10, 1));
}

// The shadow map: misses (kNoBlocker, +inf) as -1, which viewers can show.
constexpr float kNoBlockerInExr = -1.0f;
ImageF readShadowMap(const FrameResult& f, int) {
  ImageF depth = f.shadowMap.depth;
  for (float& v : depth.data)
    if (v == ShadowMap::kNoBlocker) v = kNoBlockerInExr;
  return depth;
}
void writeShadowMap(FrameResult& f, int, const ImageF& image) {
  requireChannels(image, 1, "shadowmap");
  f.shadowMap.depth = image;
  for (float& v : f.shadowMap.depth.data)
    if (v == kNoBlockerInExr) v = ShadowMap::kNoBlocker;
}

// The edge kinds in the part's channel order (normal depth background E shadow); the shadow kind
// (SSM only) is there when the frame has it.
constexpr ImageU8 EdgeImages::*kEdgeKinds[] = {&EdgeImages::normal, &EdgeImages::depth, &EdgeImages::background,
                                               &EdgeImages::combined, &EdgeImages::shadow};
ImageF readEdges(const FrameResult& f, int) {
  const EdgeImages& e = f.edges;
  if (e.combined.empty()) return {};
  const Constants& c = f.constants;
  const int kinds = e.shadow.empty() ? 4 : 5;
  ImageF out(c.width, c.height, kinds);
  for (int k = 0; k < kinds; ++k) putChannels(out, k, screen(e.*kEdgeKinds[k], c));
  return out;
}
void writeEdges(FrameResult& f, int, const ImageF& image) {
  require(image.channels == 4 || image.channels == 5,
          "part edges: " + std::to_string(image.channels) + " channels, expected 4 (5 with shadow)");
  for (int k = 0; k < image.channels; ++k) overwrite(f.edges.*kEdgeKinds[k], channels(image, k, 1), f.constants);
}

// SPEC §14's temporal part: λ_p, then h and final' (each the effect's channels), W×H.
ImageF readTemporal(const FrameResult& f, int) { return temporalPartImage(f.temporal); }
void writeTemporal(FrameResult& f, int, const ImageF& image) {
  require(image.channels == 3 || image.channels == 7,
          "part temporal: " + std::to_string(image.channels) + " channels, expected 3 (7 with RGB)");
  const int n = (image.channels - 1) / 2;
  f.temporal.weight = channels(image, 0, 1);
  f.temporal.history = channels(image, 1, n);
  f.temporal.result = channels(image, 1 + n, n);
}

}  // namespace

const PartImageAccess kGBufferImage = {[](const FrameResult& f, int l) {
                                         return validLevel(l) &&
                                                !f.levels[static_cast<size_t>(l)].gbuffer.depth.empty();
                                       },
                                       readGBuffer, writeGBuffer, nullptr};
const PartImageAccess kShadowMapImage = {[](const FrameResult& f, int) { return !f.shadowMap.depth.empty(); },
                                         readShadowMap, writeShadowMap, nullptr};
const PartImageAccess kShadowTestImage = screenImage<shadowLitOf>();
const PartImageAccess kEdgesImage = {[](const FrameResult& f, int) { return !f.edges.combined.empty(); }, readEdges,
                                     writeEdges, nullptr};
const PartImageAccess kEccentricityImage = screenImage<eccentricityOf>();
const PartImageAccess kMotionImage = screenImage<motionOf>();
const PartImageAccess kLevelLimitImage = screenImage<levelLimitOf>();
const PartImageAccess kTileRatesImage = byteImage<tileRatesOf>();
const PartImageAccess kMarksImage = byteImage<marksOf>();
const PartImageAccess kMaskImage = byteImage<maskOf>();
const PartImageAccess kAlphaImage = floatImage<alphaOf>();
const PartImageAccess kStencilImage = byteImage<stencilOf>();
const PartImageAccess kRawImage = floatImage<rawOf>();
const PartImageAccess kSubImage = floatImage<subOf>();
const PartImageAccess kUpsampleImage = floatImage<upsampleOf>();
const PartImageAccess kBlendAlphaImage = floatImage<blendAlphaOf>();
const PartImageAccess kCompositeImage = floatImage<compositeOf>();
const PartImageAccess kLevelMapImage = byteImage<levelMapOf>();
const PartImageAccess kFinalImage = floatImage<finalOf>();
const PartImageAccess kTemporalImage = {[](const FrameResult& f, int) { return !f.temporal.weight.empty(); },
                                        readTemporal, writeTemporal, nullptr};
const PartImageAccess kShadedImage = floatImage<shadedOf>();

// ---- What the rows make -----------------------------------------------------------------------

std::vector<PartRef> heldParts(const FrameResult& f) {
  std::vector<PartRef> parts;
  const Constants& c = f.constants;
  for (size_t i = 0; i < std::size(kParts);) {
    if (!kParts[i].perLevel) {
      if (holdsPart(f, kParts[i].part)) parts.push_back({kParts[i].part});
      ++i;
      continue;
    }
    size_t end = i;  // a run of per-level rows, level by level
    while (end < std::size(kParts) && kParts[end].perLevel) ++end;
    for (int l = 0; l < kLevelCount; ++l) {
      if (!c.levels[static_cast<size_t>(l)].enabled) continue;
      for (size_t k = i; k < end; ++k)
        if (holdsPart(f, kParts[k].part, l)) parts.push_back({kParts[k].part, l});
    }
    i = end;
  }
  return parts;
}

std::vector<std::string> partChannels(Part part, const ImageF& image) {
  // the effect's channel count (1, or 3 for SSGI's RGB) that names exactly the image's channels
  std::vector<std::string> names = partChannels(part, 3);
  if (static_cast<int>(names.size()) != image.channels) names = partChannels(part, 1);
  require(static_cast<int>(names.size()) >= image.channels,
          "part " + std::string(partInfo(part).name) + ": " + std::to_string(image.channels) +
              " channels, the stage list names " + std::to_string(names.size()));
  names.resize(static_cast<size_t>(image.channels));
  return names;
}

bool inputApplies(InputWhen when, const Constants& c) {
  switch (when) {
    case InputWhen::Always:
      return true;
    case InputWhen::Ssm:
      return c.effect == Effect::Ssm;
    case InputWhen::Footprint:
      return methodInfo(c.mode).masks == MaskBuilder::EffectEdges;
    case InputWhen::Peer:
      return methodInfo(c.mode).peer();
  }
  return false;
}

std::vector<std::string> partInputNames(Part part, int level, const Constants& c) {
  std::vector<std::string> names;
  const auto add = [&](Part p, int l) {
    const std::string name = partName(p, l);
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  };
  for (const PartInput& in : partInfo(part).inputs) {
    if (!inputApplies(in.when, c)) continue;
    switch (in.level) {
      case InputLevel::Same:
        add(in.part, level);
        break;
      case InputLevel::Zero:
        add(in.part, 0);
        break;
      case InputLevel::NextCoarser: {
        const int next = level >= 0 ? c.nextCoarserEnabled(level) : -1;
        if (next >= 0) add(in.part, next);
        break;
      }
      case InputLevel::Coarser:
        for (int k = level + 1; k < kLevelCount; ++k) add(in.part, k);
        break;
      case InputLevel::Every:
        for (int k = 0; k < kLevelCount; ++k) add(in.part, k);
        break;
    }
  }
  return names;
}

std::string viewCaption(Part part, int channels) {
  const PartView& v = partInfo(part).view;
  const std::string caption(v.caption);
  switch (v.display) {
    case Display::Binary:
      return caption + ": 1 white, 0 black";
    case Display::Levels:
      return caption + ": one ramp colour per value, 0 dark to 3 bright";
    case Display::Effect:
      return caption + (channels == 3 ? " (RGB)" : "") + ", clamped to [0, 1]: 0 black, 1 white";
    case Display::Scalar: {
      if (!(v.hi > v.lo)) return caption + " on the ramp over its range";
      char range[64];
      std::snprintf(range, sizeof range, " on the ramp over [%g, %g]", static_cast<double>(v.lo),
                    static_cast<double>(v.hi));
      return caption + range;
    }
    case Display::Colour:
      return caption + ", linear RGB shown sRGB-encoded";
    case Display::GBuffer:
    case Display::ShadowMap:
    case Display::Edges:
      return caption;
  }
  return caption;
}

ImageF temporalPartImage(const TemporalImages& t) {
  if (t.weight.empty()) return {};
  const int n = t.history.channels;
  ImageF out(t.weight.width, t.weight.height, 1 + 2 * n);
  putChannels(out, 0, t.weight);
  putChannels(out, 1, t.history);
  putChannels(out, 1 + n, t.result);
  return out;
}

ImageF imageChannel(const ImageF& image, int c) { return channels(image, c, 1); }

}  // namespace mrr
