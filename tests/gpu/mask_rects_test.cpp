// The port's mrr-effect mask passes drawn over the rectangles where they can be non-zero (SPEC §12
// and §12.2; docs/figures.md, "The port's mrr-effect masks, cheaper") give the bits the same
// passes give over the whole level: the widening (effect_masks.frag steps 2–3) over its reach
// past M_ℓ's blocks, and the a-posteriori refinement (refine_masks.frag with masks.frag's blur)
// near the marks' blocks, a_ℓ and S_ℓ copied elsewhere. Sparse random inputs; each fast path is
// also shown to need its whole rectangle set (narrower rectangles give other bits). The block
// maps the GPU-resident frame draws these over (gpu/blocks.h, blocks.geom) equal the host's
// (nearBlocks, blocksOf), and their runs cover each matching block's pixels once and no others.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <random>
#include <vector>

#include "common/frame.h"
#include "common/params.h"
#include "gpu/context.h"
#include "gpu/blocks.h"
#include "gpu/effect_masks.h"
#include "gpu/gbuffer.h"
#include "gpu/masks.h"
#include "gpu/program.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

using test::sameBits;

// A sparse 0/1 image: `blobs` random short runs, so whole blocks stay empty.
ImageU8 sparseMask(int w, int h, int blobs, std::mt19937& rng) {
  ImageU8 m(w, h);
  std::uniform_int_distribution<int> x(0, w - 1), y(0, h - 1), len(1, 6);
  for (int b = 0; b < blobs; ++b) {
    const int x0 = x(rng), y0 = y(rng), n = len(rng);
    for (int i = 0; i < n && x0 + i < w; ++i) m.at(x0 + i, y0) = 1;
  }
  return m;
}

// A host 0/1 image as an R8 target of the scene's pool (a block map the GPU passes read).
gpu::Target targetOf(const gpu::GpuScene& scene, const ImageU8& bits) {
  gpu::Target target = scene.target(bits.width, bits.height, 1, false, gpu::Texel::R8);
  std::vector<uint8_t> bytes(bits.data.size());
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = bits.data[i] ? 255 : 0;
  glBindTexture(GL_TEXTURE_2D, target->texture(0));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, bits.width, bits.height, GL_RED, GL_UNSIGNED_BYTE, bytes.data());
  return target;
}

TEST(GpuBlockMaps, EqualTheHostsAndTheirRunsCoverEachBlockOnce) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  Scene empty;
  const gpu::GpuScene scene(empty);
  std::mt19937 rng(5);
  const int w = 300, h = 45;  // more than two segments of 128 blocks a row, and runs cut at their words
  const ImageU8 blocks = sparseMask(w, h, 60, rng), other = sparseMask(w, h, 20, rng);
  const gpu::Target map = targetOf(scene, blocks), otherMap = targetOf(scene, other);
  for (const auto& [dx, dy] : {std::pair{0, 0}, {1, 0}, {0, 2}, {3, 1}}) {
    const ImageU8 host = nearBlocks(blocks, 1, dx, dy);
    EXPECT_EQ(gpu::dilateBlocks(scene, *map, dx, dy)->readBinary(0).data, host.data) << dx << "," << dy;
  }
  ImageU8 both = blocks;
  for (size_t i = 0; i < both.data.size(); ++i) both.data[i] |= other.data[i];
  EXPECT_EQ(gpu::uniteBlocks(scene, *map, *otherMap)->readBinary(0).data, both.data);
  EXPECT_EQ(gpu::poolBlocks(scene, *map, 2)->readBinary(0).data, gpu::blocksOf(blocks, 2).data);
  // several maps in one pass (what drawMasks draws every cover from): boxes of the grid's own map,
  // and of the grid twice as fine pooled
  const ImageU8 fine = sparseMask(2 * w, 2 * h, 80, rng);
  const gpu::Target fineMap = targetOf(scene, fine);
  const std::vector<gpu::MapSpec> specs = {{1, 0, -1, -1}, {2, 2, -1, -1}, {-1, -1, 1, 1}, {3, 1, 2, 0},
                                           {0, 0, -1, -1}, {1, 1, 0, 0},   {-1, -1, 0, 0}, {2, 0, 3, 3},
                                           {4, 4, -1, -1}};  // nine: two passes
  const std::vector<gpu::Target> maps = gpu::blockMaps(scene, *map, *fineMap, specs);
  ASSERT_EQ(maps.size(), 2u);
  for (size_t k = 0; k < specs.size(); ++k) {
    const gpu::MapSpec& m = specs[k];
    ImageU8 want(w, h);
    if (m.ax >= 0) want = nearBlocks(blocks, 1, m.ax, m.ay);
    if (m.bx >= 0) {
      const ImageU8 pooled = gpu::blocksOf(nearBlocks(fine, 1, m.bx, m.by), 2);
      for (size_t i = 0; i < want.data.size(); ++i) want.data[i] |= pooled.data[i];
    }
    EXPECT_EQ(maps[k / 8]->readBinary(static_cast<int>(k % 8)).data, want.data) << "map " << k;
  }
  ImageU8 rows((w + 7) / 8, h);  // 8 × 1 (the edge sample's diagonals)
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) rows.at(x / 8, y) |= blocks.at(x, y);
  EXPECT_EQ(gpu::poolBlocks(scene, *map, 8, 1)->readBinary(0).data, rows.data);
  // the runs of set (clear) blocks, blockSize 3 on a target cut short of the grid: every pixel of
  // a matching block drawn exactly once (additive blending counts), no other pixel. The sparse map,
  // and one of bands: boxes across the 32-block words and the 128-block segments blocks.geom reads
  // at once, tall enough to be drawn from their first row, one ending at the grid's last column,
  // and a row of alternating blocks (the most runs a segment holds)
  ImageU8 bands(w, h);
  for (const glm::ivec4& box : {glm::ivec4(20, 3, 150, 20), glm::ivec4(31, 22, 33, 44), glm::ivec4(250, 0, w, 45)})
    for (int y = box.y; y < box.w; ++y)
      for (int x = box.x; x < box.z; ++x) bands.at(x, y) = 1;
  for (int x = 0; x < w; x += 2) bands.at(x, 21) = 1;
  const gpu::Target bandMap = targetOf(scene, bands);
  const int size = 3, tw = w * size - 2, th = h * size - 1;
  const unsigned program = gpu::compileProgramFromSource(
      "blocks test", "blocks.vert", gpu::shaderSource("blocks.vert"), "count.frag",
      "#version 330 core\nlayout(location = 0) out vec4 count;\nvoid main() { count = vec4(1.0); }\n");
  for (const auto& [source, texture] : {std::pair{&blocks, map->texture(0)}, {&bands, bandMap->texture(0)}})
    for (int value : {1, 0}) {
      const gpu::Target target = scene.target(tw, th, 1, false, gpu::Texel::R32f);
      target->bind();
      const float zero[4] = {0, 0, 0, 0};
      glClearBufferfv(GL_COLOR, 0, zero);
      glUseProgram(program);
      glEnable(GL_BLEND);
      glBlendFunc(GL_ONE, GL_ONE);
      gpu::Cover cover;
      cover.blocks = texture;
      cover.blockWidth = w;
      cover.blockHeight = h;
      cover.blockSize = size;
      cover.value = value;
      scene.draw(cover, tw, th);
      glDisable(GL_BLEND);
      const ImageF drawn = target->read(0, 1);
      int wrong = 0;
      for (int y = 0; y < th; ++y)
        for (int x = 0; x < tw; ++x) {
          const float want = (source->at(x / size, y / size) != 0) == (value != 0) ? 1.0f : 0.0f;
          wrong += drawn.at(x, y) != want;
        }
      EXPECT_EQ(wrong, 0) << (source == &blocks ? "sparse" : "bands") << " map, blocks of value " << value;
    }
  glDeleteProgram(program);
}

TEST(GpuMaskRects, TheWideningOverItsReachGivesTheWholeLevelsBits) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  Scene empty;
  const gpu::GpuScene scene(empty);
  std::mt19937 rng(7);
  const int w = 96, h = 64, blockSize = 4, levelScale = 2;
  for (int cap : {1, 3, 8}) {
    const ImageU8 mask = sparseMask(w, h, 12, rng);
    ImageF footprint(w, h);
    std::uniform_real_distribution<float> reach(0.0f, 2.0f * static_cast<float>(levelScale) * (cap + 2));
    for (float& f : footprint.data) f = reach(rng);
    gpu::TextureSet textures;
    const unsigned m = textures.add(gpu::uploadBinary(mask)), f = textures.add(gpu::uploadTexture(footprint));
    // as drawMasks: M_ℓ's blocks, then those within cap along x, then along y too
    const ImageU8 blocks = gpu::blocksOf(mask, blockSize);
    const ImageU8 across = nearBlocks(blocks, blockSize, cap, 0), within = nearBlocks(across, blockSize, 0, cap);
    const auto acrossRects = gpu::blockRects(across, 1, blockSize, w, h);
    const auto withinRects = gpu::blockRects(within, 1, blockSize, w, h);
    ASSERT_LT(static_cast<size_t>(std::count(within.data.begin(), within.data.end(), 1)), within.data.size())
        << "cap " << cap << ": the rectangles cover the whole level, nothing is skipped";
    const gpu::Target wholeTarget = gpu::drawDilateByReach(scene, m, 0, f, w, h, levelScale, cap);
    const ImageU8 whole = wholeTarget->readBinary(0);
    const ImageU8 fast = gpu::drawDilateByReach(scene, m, 0, f, w, h, levelScale, cap, gpu::Cover::over(&acrossRects),
                                                gpu::Cover::over(&withinRects))
                             ->readBinary(0);
    EXPECT_EQ(fast.data, whole.data) << "cap " << cap;
    // the same over block maps on the GPU, as the resident frame draws it
    const gpu::Target acrossMap = targetOf(scene, across), withinMap = targetOf(scene, within);
    const ImageU8 byBlocks =
        gpu::drawDilateByReach(scene, m, 0, f, w, h, levelScale, cap, gpu::Cover::blocksOf(*acrossMap, blockSize),
                               gpu::Cover::blocksOf(*withinMap, blockSize))
            ->readBinary(0);
    EXPECT_EQ(byBlocks.data, whole.data) << "cap " << cap;
    EXPECT_NE(whole.data, mask.data) << "cap " << cap << ": the widening added nothing";
    // SPEC §12.3's M'_ℓ ∧ ¬M_ℓ likewise
    const unsigned widened = wholeTarget->texture(0);
    const ImageU8 onlyWhole = gpu::drawWideningOnly(scene, widened, m, 0, w, h)->readBinary(0);
    EXPECT_EQ(gpu::drawWideningOnly(scene, widened, m, 0, w, h, gpu::Cover::over(&withinRects))->readBinary(0).data,
              onlyWhole.data)
        << "cap " << cap;
    // the rectangles of M_ℓ's own blocks alone miss what the widening reaches past them
    const auto own = gpu::blockRects(blocks, 1, blockSize, w, h);
    const ImageU8 narrow =
        gpu::drawDilateByReach(scene, m, 0, f, w, h, levelScale, cap, gpu::Cover::over(&own), gpu::Cover::over(&own))
            ->readBinary(0);
    if (cap >= blockSize) EXPECT_NE(narrow.data, whole.data) << "cap " << cap;
  }
}

// One level's refinement on masks drawn from host E and F, with and without the marks' blocks
// (a block map on the GPU).
struct Refined {
  std::array<MaskLevel, kLevelCount> masks;
  bool wholeLevel = false;  // S_ℓ's support: the whole level
  ImageU8 support;          // else its block map, read back
};

Refined refine(const gpu::GpuScene& scene, const ImageU8& edges, const ImageF& footprint, const ImageU8& marks,
               const Constants& c, int level, const ImageU8* marksBlocks) {
  gpu::TextureSet textures;
  const unsigned e = textures.add(gpu::uploadBinary(edges)), f = textures.add(gpu::uploadTexture(footprint));
  auto targets = gpu::drawMasks(scene, e, 0, c, [&](const gpu::Cover&) { return f; });
  gpu::Target marksTarget = targetOf(scene, marks);
  const gpu::Target blocksTarget = marksBlocks ? targetOf(scene, *marksBlocks) : gpu::Target();
  gpu::refineMasks(scene, *targets, level, std::move(marksTarget), c,
                   blocksTarget ? gpu::BlockMap(*blocksTarget) : gpu::BlockMap());
  const gpu::BlockMap& support = targets->supportBlocks[static_cast<size_t>(level)];
  Refined r{gpu::readMasks(*targets, c, false), !support, {}};
  if (support) r.support = support.target->readBinary(support.attachment);
  return r;
}

TEST(GpuMaskRects, RefiningNearTheMarksGivesTheWholeLevelsBits) {
  MRR_REQUIRE_GL_OR_SKIP();
  gpu::GlContext context;
  Scene empty;
  const gpu::GpuScene scene(empty);
  std::mt19937 rng(11);
  Settings s = defaultSettings(Effect::Ssao);
  s.width = 160;
  s.height = 96;
  s.mode = Mode::MrrEffect;
  s.effectMask.cap = 4;
  s.effectMask.posterior = 0.05f;
  const Constants c = makeConstants(s, 10.0f);
  const int w = c.paddedWidth, h = c.paddedHeight;
  const ImageU8 edges = sparseMask(w, h, 10, rng);
  ImageF footprint(w, h);
  std::uniform_real_distribution<float> reach(0.0f, 24.0f);
  for (size_t i = 0; i < footprint.data.size(); ++i)
    if (edges.data[i]) footprint.data[i] = reach(rng);
  for (int level = 0; level < c.coarsestEnabled; ++level) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(level)];
    if (!lc.enabled) continue;
    const int blockSize = 1 << (kLevelCount - 1 - level);  // level pixels per block of the coarsest grid
    for (int blobs : {0, 3}) {  // no mark (a_ℓ, S_ℓ kept), then a few
      const ImageU8 marks = sparseMask(lc.width, lc.height, blobs, rng);
      const ImageU8 blocks = gpu::blocksOf(marks, blockSize);
      const Refined whole = refine(scene, edges, footprint, marks, c, level, nullptr);
      const Refined fast = refine(scene, edges, footprint, marks, c, level, &blocks);
      const std::string where = "level " + std::to_string(level) + ", " + std::to_string(blobs) + " marks";
      for (size_t l = 0; l < kLevelCount; ++l) {
        EXPECT_EQ(fast.masks[l].mask.data, whole.masks[l].mask.data) << where << ", M_" << l;
        EXPECT_EQ(fast.masks[l].stencil.data, whole.masks[l].stencil.data) << where << ", S_" << l;
        EXPECT_TRUE(sameBits(fast.masks[l].alpha, whole.masks[l].alpha)) << where << ", a_" << l;
      }
      EXPECT_TRUE(whole.wholeLevel) << where;
      ASSERT_FALSE(fast.wholeLevel) << where;  // S_ℓ's blocks, for the effect's fill
      for (int y = 0; y < lc.height; ++y)  // and they hold every pixel of S_ℓ
        for (int x = 0; x < lc.width; ++x) {
          if (!fast.masks[static_cast<size_t>(level)].stencil.at(x, y)) continue;
          ASSERT_TRUE(fast.support.at(x / blockSize, y / blockSize)) << where << ": S_ℓ at " << x << "," << y
                                                                    << " outside its blocks";
        }
      if (blobs == 0) continue;
      // the marks' blocks are what makes it exact: without them (an empty grid) the marks are lost
      const ImageU8 none(blocks.width, blocks.height);
      const Refined blind = refine(scene, edges, footprint, marks, c, level, &none);
      EXPECT_FALSE(sameBits(blind.masks[static_cast<size_t>(level)].alpha, whole.masks[static_cast<size_t>(level)].alpha))
          << where;
    }
  }
}

}  // namespace
}  // namespace mrr
