#include "compare/parity/against.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "common/error.h"
#include "common/image_io.h"
#include "common/stage_images.h"
#include "common/stages.h"
#include "compare/report/report.h"

namespace mrr {

namespace {
namespace fs = std::filesystem;

int levelOf(const std::string& name) {
  const size_t at = name.find(".L");
  return at == std::string::npos ? -1 : std::stoi(name.substr(at + 2));
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
    writePart(f.frame, part, levelOf(g.name), image);  // the inverse of stageParts: the row's accessor
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
      const std::vector<std::string> sources = partInputNames(part, row.level, c);  // the row's inputs
      const bool own = std::any_of(sources.begin(), sources.end(), [&](const std::string& s) { return foreign.supplied.count(s) > 0; });
      if (!own) row.sameInput.reset();  // on the oracle's own inputs it would only repeat end to end, stricter
    }
    result.rows.push_back(std::move(row));
  }
  return result;
}

}  // namespace mrr
