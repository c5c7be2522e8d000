#include "compare/parity/against.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "common/error.h"
#include "common/image_io.h"
#include "common/stages.h"
#include "compare/report/report.h"

namespace mrr {

namespace {
namespace fs = std::filesystem;

ImageU8 toBytes(const ImageF& image) {
  ImageU8 out(image.width, image.height, image.channels);
  for (size_t i = 0; i < image.data.size(); ++i) out.data[i] = static_cast<uint8_t>(std::lround(std::max(image.data[i], 0.0f)));
  return out;
}

// Channel `c` of `image` as a one-channel image.
ImageF channel(const ImageF& image, int c) {
  ImageF out(image.width, image.height, 1);
  for (size_t p = 0; p < out.data.size(); ++p) out.data[p] = image.data[p * static_cast<size_t>(image.channels) + static_cast<size_t>(c)];
  return out;
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

// Writes the top-left of `padded` (the full-res grids are padded, SPEC §0) from `image`.
void overwrite(ImageU8& padded, const ImageF& image) {
  for (int y = 0; y < image.height && y < padded.height; ++y)
    for (int x = 0; x < image.width && x < padded.width; ++x)
      padded.at(x, y) = static_cast<uint8_t>(std::lround(std::max(image.at(x, y), 0.0f)));
}

int levelOf(const std::string& name) {
  const size_t at = name.find(".L");
  return at == std::string::npos ? -1 : std::stoi(name.substr(at + 2));
}

// The inverse of stageParts (compare/report/report.cpp): `image` (in the part's channel order) in
// place of the frame's own stage.
void putPart(FrameResult& f, Part part, int level, const ImageF& image) {
  const size_t l = level < 0 ? 0 : static_cast<size_t>(level);
  LevelResult& lr = f.levels[l];
  switch (part) {
    case Part::GBuffer: {
      GBuffer& g = lr.gbuffer;
      g.depth = channel(image, 0);
      g.position = channels(image, 1, 3);
      g.normal = channels(image, 4, 3);
      g.albedo = channels(image, 7, 3);
      g.hit = toBytes(channel(image, 10));
      break;
    }
    case Part::ShadowMap: {
      ImageF depth = image;
      for (float& v : depth.data)
        if (v == -1.0f) v = ShadowMap::kNoBlocker;  // stageParts writes misses as -1
      f.shadowMap.depth = depth;
      break;
    }
    case Part::ShadowTest: overwrite(f.shadowLit, image); break;
    case Part::Edges: {
      ImageU8* kinds[] = {&f.edges.normal, &f.edges.depth, &f.edges.background, &f.edges.combined, &f.edges.shadow};
      for (int k = 0; k < image.channels; ++k) overwrite(*kinds[k], channel(image, k));
      break;
    }
    case Part::TileRates: f.tileRates = toBytes(image); break;
    case Part::Eccentricity: f.eccentricity = image; break;  // SPEC §13
    case Part::Motion: f.motion = image; break;
    case Part::LevelLimit: f.levelLimit = toBytes(image); break;
    case Part::Marks: lr.marks = toBytes(image); break;  // SPEC §12.2
    case Part::Mask: lr.masks.mask = toBytes(image); break;
    case Part::Alpha: lr.masks.alpha = image; break;
    case Part::Stencil: lr.masks.stencil = toBytes(image); break;
    case Part::Raw: lr.raw = image; break;
    case Part::Sub: lr.sub = image; break;
    case Part::Upsample: f.blend.upsampled[l] = image; break;
    case Part::BlendAlpha: f.blend.alpha[l] = image; break;
    case Part::Composite: f.blend.composite[l] = image; break;
    case Part::LevelMap: f.blend.levelMap = toBytes(image); break;
    case Part::Final: f.blend.final = image; break;
    case Part::Temporal: {  // SPEC §14: h in the first channels, λ_p in the last
      f.temporal.history = channels(image, 0, image.channels - 1);
      f.temporal.weight = channel(image, image.channels - 1);
      break;
    }
    case Part::Shaded: f.shaded = image; break;
  }
}

// The parts a row's same-input check reads from the frame compared (compare/parity/parity.cpp): the
// oracle's function runs on these.
std::vector<std::string> sameInputSources(Part part, int level, const Constants& c) {
  const bool shadowMap = c.needsShadowMap();
  const auto at = [&](Part p) { return partName(p, level); };
  switch (part) {
    case Part::ShadowTest: return {partName(Part::GBuffer, 0), partName(Part::ShadowMap)};
    case Part::Edges: {
      std::vector<std::string> in = {partName(Part::GBuffer, 0)};
      if (c.effect == Effect::Ssm) in.push_back(partName(Part::ShadowTest));
      return in;
    }
    case Part::Marks: {  // SPEC §12.2: the next coarser enabled level's result, stencil and G-buffer
      const int next = c.nextCoarserEnabled(level);
      std::vector<std::string> in;
      if (next >= 0) in = {partName(Part::Sub, next), partName(Part::Stencil, next), partName(Part::GBuffer, next)};
      if (c.foveation.active()) in.push_back(partName(Part::LevelLimit));
      return in;
    }
    case Part::TileRates:
    case Part::Mask:
    case Part::Alpha:
    case Part::Stencil: return {partName(Part::Edges), partName(Part::TileRates)};
    case Part::Raw: {
      std::vector<std::string> in = {at(Part::GBuffer), at(Part::Stencil)};
      if (shadowMap) in.push_back(partName(Part::ShadowMap));
      return in;
    }
    case Part::Sub: return {at(Part::Raw), at(Part::Stencil), at(Part::GBuffer)};
    case Part::Upsample:
    case Part::BlendAlpha:
    case Part::Composite: {
      std::vector<std::string> in = {at(Part::Sub), at(Part::Stencil), at(Part::Alpha), at(Part::Upsample),
                                     at(Part::BlendAlpha)};
      for (int k = level + 1; k < kLevelCount; ++k) in.push_back(partName(Part::Composite, k));
      return in;
    }
    case Part::Final: {
      std::vector<std::string> in;
      for (int k = 0; k < kLevelCount; ++k) {
        in.push_back(partName(Part::Composite, k));
        in.push_back(partName(Part::Sub, k));
      }
      return in;
    }
    case Part::Shaded: return {partName(Part::GBuffer, 0), partName(Part::Final), partName(Part::ShadowTest)};
    default: return {};
  }
}
}  // namespace

ForeignStages readForeignStages(const std::string& path, const FrameResult& oracle) {
  std::error_code ec;
  require(fs::exists(path, ec), "--against " + path + ": no such file or folder");
  // The file's parts, by name: a multi-part EXR, or a folder of PART.exr.
  std::vector<ExrPart> given;
  if (fs::is_directory(path, ec)) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(path, ec))
      if (e.path().extension() == ".exr") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    require(!files.empty(), "--against " + path + ": the folder holds no PART.exr file (e.g. final.exr)");
    for (const fs::path& file : files) {
      std::vector<ExrPart> parts = readParts(file.string());
      require(!parts.empty(), "--against " + file.string() + ": no image in the file");
      parts.front().name = file.stem().string();
      given.push_back(std::move(parts.front()));
    }
  } else {
    given = readParts(path);
  }

  const Constants& c = oracle.constants;
  const std::vector<ExrPart> expected = stageParts(oracle);
  ForeignStages f;
  f.source = path;
  f.frame = oracle;
  std::string known;
  for (const ExrPart& e : expected) known += (known.empty() ? "" : ", ") + e.name;
  for (const ExrPart& g : given) {
    Part part;
    if (!partOf(g.name, part)) {
      f.ignored.push_back(g.name);
      continue;
    }
    const auto e = std::find_if(expected.begin(), expected.end(), [&](const ExrPart& x) { return x.name == g.name; });
    require(e != expected.end(), "--against " + path + ": part " + g.name + " is no stage of the oracle's " +
                                     toString(c.effect) + " " + toString(c.mode) + " frame (its stages: " + known + ")");
    require(g.image.width == e->image.width && g.image.height == e->image.height,
            "--against " + path + ": part " + g.name + " is " + std::to_string(g.image.width) + "x" +
                std::to_string(g.image.height) + ", expected " + std::to_string(e->image.width) + "x" +
                std::to_string(e->image.height) + " (the oracle's frame at --size " + std::to_string(c.width) + "x" +
                std::to_string(c.height) + ")");
    // The channels in the part's order, found by name.
    ImageF image(g.image.width, g.image.height, static_cast<int>(e->channelNames.size()));
    std::string channelsGiven;
    for (const std::string& n : g.channelNames) channelsGiven += (channelsGiven.empty() ? "" : " ") + n;
    for (size_t k = 0; k < e->channelNames.size(); ++k) {
      const auto at = std::find(g.channelNames.begin(), g.channelNames.end(), e->channelNames[k]);
      require(at != g.channelNames.end(), "--against " + path + ": part " + g.name + " lacks channel " +
                                              e->channelNames[k] + " (it has " + channelsGiven + ")");
      const size_t from = static_cast<size_t>(at - g.channelNames.begin());
      for (size_t p = 0; p < image.pixelCount(); ++p)
        image.data[p * e->channelNames.size() + k] = g.image.data[p * g.channelNames.size() + from];
    }
    putPart(f.frame, part, levelOf(g.name), image);
    f.supplied.insert(g.name);
  }
  require(!f.supplied.empty(), "--against " + path + ": not a stages file: no part is named like a stage of " +
                                   "`mrr render --stages` (" + known + ")");
  for (const ExrPart& e : expected)
    if (!f.supplied.count(e.name)) f.absent.push_back(e.name);
  return f;
}

ParityResult compareForeign(const FrameResult& oracle, const ForeignStages& foreign, const DirectionalLight& light) {
  const ParityResult all = compareFrames(oracle, foreign.frame, light);
  ParityResult result;
  result.effect = all.effect;
  const Constants& c = oracle.constants;
  for (StageRow row : all.rows) {
    Part part;
    if (!partOf(row.stage, part)) continue;  // the never-slower decision: the file has none
    const std::string key = partName(part, row.level);
    if (!foreign.supplied.count(key)) continue;
    if (row.sameInput && row.endToEnd) {
      const std::vector<std::string> sources = sameInputSources(part, row.level, c);
      const bool own = std::any_of(sources.begin(), sources.end(), [&](const std::string& s) { return foreign.supplied.count(s) > 0; });
      if (!own) row.sameInput.reset();  // on the oracle's own inputs it would only repeat end to end, stricter
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace mrr
