// The port's mrr-effect mask passes drawn over the rectangles where they can be non-zero (SPEC §12
// and §12.2; docs/figures.md, "The port's mrr-effect masks, cheaper") give the bits the same
// passes give over the whole level: the widening (effect_masks.frag steps 2–3) over its reach
// past M_ℓ's blocks, and the a-posteriori refinement (refine_masks.frag with masks.frag's blur)
// near the marks' blocks, a_ℓ and S_ℓ copied elsewhere. Sparse random inputs; each fast path is
// also shown to need its whole rectangle set (narrower rectangles give other bits).
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
#include "gpu/effect_masks.h"
#include "gpu/gbuffer.h"
#include "gpu/masks.h"
#include "tests/gpu/gl_test.h"

namespace mrr {
namespace {

bool sameBits(const ImageF& a, const ImageF& b) {
  return a.width == b.width && a.height == b.height && a.data.size() == b.data.size() &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

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
    const ImageU8 fast =
        gpu::drawDilateByReach(scene, m, 0, f, w, h, levelScale, cap, &acrossRects, &withinRects)->readBinary(0);
    EXPECT_EQ(fast.data, whole.data) << "cap " << cap;
    EXPECT_NE(whole.data, mask.data) << "cap " << cap << ": the widening added nothing";
    // SPEC §12.3's M'_ℓ ∧ ¬M_ℓ likewise
    const unsigned widened = wholeTarget->texture(0);
    const ImageU8 onlyWhole = gpu::drawWideningOnly(scene, widened, m, 0, w, h)->readBinary(0);
    EXPECT_EQ(gpu::drawWideningOnly(scene, widened, m, 0, w, h, &withinRects)->readBinary(0).data, onlyWhole.data)
        << "cap " << cap;
    // the rectangles of M_ℓ's own blocks alone miss what the widening reaches past them
    const auto own = gpu::blockRects(blocks, 1, blockSize, w, h);
    const ImageU8 narrow = gpu::drawDilateByReach(scene, m, 0, f, w, h, levelScale, cap, &own, &own)->readBinary(0);
    if (cap >= blockSize) EXPECT_NE(narrow.data, whole.data) << "cap " << cap;
  }
}

// One level's refinement on masks drawn from host E and F, with and without the marks' blocks.
struct Refined {
  std::array<MaskLevel, kLevelCount> masks;
  std::vector<glm::ivec4> supportRects;
};

Refined refine(const gpu::GpuScene& scene, const ImageU8& edges, const ImageF& footprint, const ImageU8& marks,
               const Constants& c, int level, const ImageU8* marksBlocks) {
  gpu::TextureSet textures;
  const unsigned e = textures.add(gpu::uploadBinary(edges)), f = textures.add(gpu::uploadTexture(footprint));
  auto targets = gpu::drawMasks(scene, e, 0, c, [&](const std::vector<glm::ivec4>&) { return f; });
  gpu::Target marksTarget = scene.target(marks.width, marks.height, 1, false, gpu::Texel::R8);
  std::vector<uint8_t> bytes(marks.data.size());
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = marks.data[i] ? 255 : 0;
  glBindTexture(GL_TEXTURE_2D, marksTarget->texture(0));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, marks.width, marks.height, GL_RED, GL_UNSIGNED_BYTE, bytes.data());
  gpu::refineMasks(scene, *targets, level, std::move(marksTarget), c, marksBlocks);
  return {gpu::readMasks(*targets, c, false), targets->supportRects[static_cast<size_t>(level)]};
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
      EXPECT_TRUE(whole.supportRects.empty()) << where;  // the whole level
      EXPECT_FALSE(fast.supportRects.empty()) << where;  // S_ℓ's rectangles, for the effect's fill
      for (int y = 0; y < lc.height; ++y)  // and they hold every pixel of S_ℓ
        for (int x = 0; x < lc.width; ++x) {
          if (!fast.masks[static_cast<size_t>(level)].stencil.at(x, y)) continue;
          bool inside = false;
          for (const glm::ivec4& r : fast.supportRects) inside |= x >= r.x && x < r.z && y >= r.y && y < r.w;
          ASSERT_TRUE(inside) << where << ": S_ℓ at " << x << "," << y << " outside its rectangles";
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
