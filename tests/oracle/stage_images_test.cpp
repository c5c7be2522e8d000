// The stage list's accessors (common/stage_images.h) on real oracle frames: every row's image
// reads back as written, in a frame that holds only the constants and in a copy of the frame
// itself (what `compare --against` does: padded grids keep their padding); every image lies on
// its row's grid with the channels its row names; and the stages EXR keeps its order.
#include "common/stage_images.h"

#include <gtest/gtest.h>

#include <cstring>
#include <set>

#include "common/error.h"
#include "compare/report/report.h"
#include "tests/oracle/render_helpers.h"

namespace mrr {
namespace {

bool bitIdentical(const ImageF& a, const ImageF& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels && a.data.size() == b.data.size() &&
         (a.data.empty() || std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0);
}
template <class T>
bool same(const Image<T>& a, const Image<T>& b) {
  return a.width == b.width && a.height == b.height && a.channels == b.channels && a.data.size() == b.data.size() &&
         (a.data.empty() || std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(T)) == 0);
}

// Every image a FrameResult holds, on its own (padded) grid, compared bit for bit: names the first that differs.
std::string firstDifference(const FrameResult& a, const FrameResult& b) {
  for (size_t l = 0; l < static_cast<size_t>(kLevelCount); ++l) {
    const LevelResult &x = a.levels[l], &y = b.levels[l];
    const std::string L = ".L" + std::to_string(l);
    if (!same(x.gbuffer.depth, y.gbuffer.depth) || !same(x.gbuffer.position, y.gbuffer.position) ||
        !same(x.gbuffer.normal, y.gbuffer.normal) || !same(x.gbuffer.albedo, y.gbuffer.albedo) ||
        !same(x.gbuffer.hit, y.gbuffer.hit) || x.gbuffer.width != y.gbuffer.width ||
        x.gbuffer.height != y.gbuffer.height)
      return "gbuffer" + L;
    if (!same(x.marks, y.marks)) return "marks" + L;
    if (!same(x.masks.mask, y.masks.mask)) return "mask" + L;
    if (!same(x.masks.alpha, y.masks.alpha)) return "alpha" + L;
    if (!same(x.masks.stencil, y.masks.stencil)) return "stencil" + L;
    if (!same(x.raw, y.raw)) return "raw" + L;
    if (!same(x.sub, y.sub)) return "sub" + L;
    if (!same(a.blend.upsampled[l], b.blend.upsampled[l])) return "upsample" + L;
    if (!same(a.blend.alpha[l], b.blend.alpha[l])) return "blendalpha" + L;
    if (!same(a.blend.composite[l], b.blend.composite[l])) return "composite" + L;
  }
  if (!same(a.shadowMap.depth, b.shadowMap.depth)) return "shadowmap";
  if (!same(a.shadowLit, b.shadowLit)) return "shadowtest";
  const EdgeImages &e = a.edges, &g = b.edges;
  if (!same(e.normal, g.normal) || !same(e.depth, g.depth) || !same(e.background, g.background) ||
      !same(e.shadow, g.shadow) || !same(e.combined, g.combined))
    return "edges";
  if (!same(a.eccentricity, b.eccentricity)) return "eccentricity";
  if (!same(a.motion, b.motion)) return "motion";
  if (!same(a.levelLimit, b.levelLimit)) return "levellimit";
  if (!same(a.tileRates, b.tileRates)) return "tilerates";
  if (!same(a.blend.levelMap, b.blend.levelMap)) return "levelmap";
  if (!same(a.blend.final, b.blend.final)) return "final";
  if (!same(a.shaded, b.shaded)) return "shaded";
  return "";
}

// Three small frames that between them hold every part: SSM with mrr-effect's marks, a gaze and
// motion (the shadow map and test, the shadow edges, the level limit); SSGI (RGB effect parts, a
// disabled level); SSAO tiles (the tile rates).
struct Frames {
  std::vector<test::Rendered> rendered;
  Frames() {
    Settings ssm = defaultSettings(Effect::Ssm);
    ssm.width = 72;
    ssm.height = 44;
    ssm.mode = Mode::MrrEffect;
    ssm.neverSlower = false;
    ssm.ssm.samples = 4;
    ssm.ssm.shadowMapSize = 64;
    ssm.effectMask.posterior = 0.02f;
    ssm.foveation.gaze = true;
    ssm.foveation.gazeX = 20;
    ssm.foveation.gazeY = 10;
    ssm.foveation.ppd = 4.0f;  // a small screen seen from afar: the periphery coarsens
    ssm.foveation.motion = ssm.foveation.panned = true;
    ssm.foveation.pan = 0.3f;
    Settings ssgi = defaultSettings(Effect::Ssgi);
    ssgi.width = 64;
    ssgi.height = 40;
    ssgi.ssgi.samples = 4;
    ssgi.ssm.shadowMapSize = 64;
    ssgi.neverSlower = false;
    rendered.push_back(test::renderScene("builtin:demo", ssm));
    rendered.push_back(test::renderScene("builtin:demo", ssgi));
    rendered.push_back(test::renderScene("builtin:demo", test::ssaoSettings(70, 42, 4, Mode::Tiles)));
  }
};

const Frames& frames() {
  static const Frames f;
  return f;
}

// The size its row's grid gives a part's image.
std::pair<int, int> gridSize(const FrameResult& f, Part part, int level) {
  const Constants& c = f.constants;
  switch (partInfo(part).grid) {
    case Grid::Level:
      return {c.levels[static_cast<size_t>(level)].width, c.levels[static_cast<size_t>(level)].height};
    case Grid::Screen:
      return {c.width, c.height};
    case Grid::Tiles:
      return {(c.paddedWidth + kTileSize - 1) / kTileSize, (c.paddedHeight + kTileSize - 1) / kTileSize};
    case Grid::Light:
      return {c.ssm.shadowMapSize, c.ssm.shadowMapSize};
  }
  return {-1, -1};
}

TEST(StageImages, EveryRowsImageRoundTripsOnARealFrame) {
  std::set<Part> seen;
  for (const test::Rendered& r : frames().rendered) {
    const FrameResult& frame = r.frame;
    const std::string which = toString(frame.constants.effect) + " " + toString(frame.constants.mode);
    for (const PartRef& ref : heldParts(frame)) {
      const std::string at = which + ": " + ref.name();
      const PartImageAccess* access = partInfo(ref.part).image;
      ASSERT_TRUE(access && access->holds && access->read && access->write) << at << ": the row has no accessor";
      seen.insert(ref.part);
      const ImageF image = readPart(frame, ref.part, ref.level);
      ASSERT_FALSE(image.empty()) << at << ": held but read empty";
      EXPECT_EQ(std::pair(image.width, image.height), gridSize(frame, ref.part, ref.level)) << at;
      EXPECT_EQ(partChannels(ref.part, image).size(), static_cast<size_t>(image.channels)) << at;

      // Into a frame that holds nothing but the constants: read back, bit for bit.
      FrameResult empty;
      empty.constants = frame.constants;
      EXPECT_FALSE(holdsPart(empty, ref.part, ref.level)) << at;
      EXPECT_TRUE(readPart(empty, ref.part, ref.level).empty()) << at;
      writePart(empty, ref.part, ref.level, image);
      EXPECT_TRUE(holdsPart(empty, ref.part, ref.level)) << at;
      EXPECT_TRUE(bitIdentical(readPart(empty, ref.part, ref.level), image)) << at << ": read, written, read again";

      // Into a copy of the frame itself: the frame is unchanged, padding included.
      FrameResult copy = frame;
      writePart(copy, ref.part, ref.level, image);
      EXPECT_EQ(firstDifference(copy, frame), "") << at << ": written back over its own image";
    }
  }
  for (const PartInfo& p : kParts) EXPECT_TRUE(seen.count(p.part)) << p.name << ": no test frame holds it";
}

// A part a frame does not hold reads empty, and a per-level part outside the levels is refused.
TEST(StageImages, AbsentPartsReadEmptyAndBadLevelsAreRefused) {
  const FrameResult& ssgi = frames().rendered[1].frame;  // level 1 disabled (Table 1), no tiles, no gaze
  ASSERT_FALSE(ssgi.constants.levels[1].enabled);
  for (const Part p : {Part::TileRates, Part::Eccentricity, Part::Motion, Part::LevelLimit}) {
    EXPECT_FALSE(holdsPart(ssgi, p)) << partName(p);
    EXPECT_TRUE(readPart(ssgi, p).empty()) << partName(p);
  }
  EXPECT_FALSE(holdsPart(ssgi, Part::GBuffer, 1));
  EXPECT_TRUE(readPart(ssgi, Part::Marks, 0).empty());
  FrameResult f = ssgi;
  for (const PartInfo& p : kParts) {
    if (!p.perLevel) continue;
    for (const int bad : {-1, kLevelCount}) {
      EXPECT_FALSE(holdsPart(ssgi, p.part, bad)) << p.name << " at " << bad;
      EXPECT_TRUE(readPart(ssgi, p.part, bad).empty()) << p.name << " at " << bad;
      EXPECT_THROW(writePart(f, p.part, bad, ImageF(4, 4, 1, 0.0f)), MrrError) << p.name << " at " << bad;
    }
  }
  // The shadow map's misses are -1 in the part and no blocker in the frame.
  const ImageF map = readPart(ssgi, Part::ShadowMap);
  size_t misses = 0;
  for (size_t i = 0; i < map.data.size(); ++i)
    if (ssgi.shadowMap.depth.data[i] == ShadowMap::kNoBlocker) misses += map.data[i] == -1.0f;
  EXPECT_GT(misses, 0u) << "the demo's light misses the bounds' corners";
}

// The stages EXR's parts: the G-buffers first; then shadowmap, shadowtest, edges, eccentricity,
// motion, levellimit, tilerates; then per level marks, mask, alpha, stencil, raw, sub, upsample,
// blendalpha, composite; then levelmap, final, shaded. Each with the row's channels.
TEST(StageImages, TheStagesExrKeepsItsPartsOrderAndChannels) {
  const FrameResult& f = frames().rendered[0].frame;  // SSM, mrr-effect with marks, gaze and motion
  std::vector<std::string> expected;
  for (int l = 0; l < kLevelCount; ++l) expected.push_back("gbuffer.L" + std::to_string(l));
  for (const char* p : {"shadowmap", "shadowtest", "edges", "eccentricity", "motion", "levellimit"})
    expected.push_back(p);
  for (int l = 0; l < kLevelCount; ++l)
    for (const char* p : {"marks", "mask", "alpha", "stencil", "raw", "sub", "upsample", "blendalpha", "composite"})
      if (std::string(p) != "marks" || !f.levels[static_cast<size_t>(l)].marks.empty())
        expected.push_back(std::string(p) + ".L" + std::to_string(l));
  for (const char* p : {"levelmap", "final", "shaded"}) expected.push_back(p);
  const std::vector<ExrPart> parts = stageParts(f);
  std::vector<std::string> names;
  for (const ExrPart& p : parts) names.push_back(p.name);
  EXPECT_EQ(names, expected);
  ASSERT_FALSE(f.levels[0].marks.empty() && f.levels[1].marks.empty()) << "the frame refines some level";
  const auto channelsOf = [&](const std::string& name) {
    for (const ExrPart& p : parts)
      if (p.name == name) return p.channelNames;
    return std::vector<std::string>{};
  };
  EXPECT_EQ(channelsOf("gbuffer.L2"), (std::vector<std::string>{"depth", "P.x", "P.y", "P.z", "N.x", "N.y", "N.z",
                                                                "albedo.R", "albedo.G", "albedo.B", "hit"}));
  EXPECT_EQ(channelsOf("edges"), (std::vector<std::string>{"normal", "depth", "background", "E", "shadow"}));
  EXPECT_EQ(channelsOf("levellimit"), (std::vector<std::string>{"fovea", "motion", "limit"}));
  EXPECT_EQ(channelsOf("raw.L1"), std::vector<std::string>{"c_raw"});
  EXPECT_EQ(channelsOf("final"), std::vector<std::string>{"Y"});
  // SSGI's effect parts are RGB; SSAO's edges have no shadow kind; tiles write their rates.
  const std::vector<ExrPart> ssgi = stageParts(frames().rendered[1].frame);
  for (const ExrPart& p : ssgi)
    if (p.name == "composite.L2")
      EXPECT_EQ(p.channelNames, (std::vector<std::string>{"c_prime.R", "c_prime.G", "c_prime.B"}));
  const std::vector<ExrPart> tiles = stageParts(frames().rendered[2].frame);
  std::vector<std::string> tileNames;
  for (const ExrPart& p : tiles) tileNames.push_back(p.name);
  const auto edges = std::find(tileNames.begin(), tileNames.end(), "edges");
  ASSERT_NE(edges, tileNames.end());
  EXPECT_EQ(*(edges + 1), "tilerates");
  EXPECT_EQ(tiles[static_cast<size_t>(edges - tileNames.begin())].channelNames,
            (std::vector<std::string>{"normal", "depth", "background", "E"}));
}

}  // namespace
}  // namespace mrr
