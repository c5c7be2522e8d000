#include "common/frame.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "common/parallel.h"

namespace mrr {

GBuffer GBuffer::uninitialised(int w, int h) {
  GBuffer g;
  g.width = w;
  g.height = h;
  g.depth = ImageF::uninitialised(w, h, 1);
  g.position = ImageF::uninitialised(w, h, 3);
  g.normal = ImageF::uninitialised(w, h, 3);
  g.albedo = ImageF::uninitialised(w, h, 3);
  g.hit = ImageU8::uninitialised(w, h, 1);
  return g;
}

ShadowMap shadowMapFrame(const DirectionalLight& light, const Bounds& bounds, int size) {
  ShadowMap m;
  m.size = size;
  // 1. light basis: forward along the light, right/up spanning the light plane
  m.forward = glm::normalize(light.direction);
  const glm::vec3 reference = std::fabs(m.forward.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
  m.right = glm::normalize(glm::cross(m.forward, reference));
  m.up = glm::cross(m.right, m.forward);
  // 2. fit a square to the bounds' eight corners seen from the light
  glm::vec3 lo(3.0e38f), hi(-3.0e38f);
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 corner((i & 1) ? bounds.hi.x : bounds.lo.x, (i & 2) ? bounds.hi.y : bounds.lo.y,
                           (i & 4) ? bounds.hi.z : bounds.lo.z);
    const glm::vec3 l(glm::dot(corner, m.right), glm::dot(corner, m.up), glm::dot(corner, m.forward));
    lo = glm::min(lo, l);
    hi = glm::max(hi, l);
  }
  const float extent = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 1.001f;
  const float margin = 0.01f * extent;
  m.texel = extent / static_cast<float>(size);
  const float u0 = 0.5f * (lo.x + hi.x) - 0.5f * extent, v0 = 0.5f * (lo.y + hi.y) - 0.5f * extent;
  m.origin = m.right * u0 + m.up * v0 + m.forward * (lo.z - margin);
  m.farDepth = (hi.z - lo.z) + 2.0f * margin;  // every hit lies in [margin, hi.z − lo.z + margin]
  return m;
}

Masks fullModeMasks(const Constants& c) {
  Masks levels;
  const LevelConstants& l0 = c.levels[0];
  levels[0].alpha = ImageF(l0.width, l0.height, 1, 1.0f);
  levels[0].stencil = ImageU8(l0.width, l0.height);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) levels[0].stencil.at(x, y) = 1;
  return levels;
}

Masks uniformMasks(const Constants& c) {
  // levelExtent (frame.h): the level pixels a full-res pixel can take its value from
  Masks levels;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    MaskLevel& ml = levels[static_cast<size_t>(l)];
    ml.stencil = ImageU8(lc.width, lc.height);
    ml.alpha = ImageF(lc.width, lc.height);
    if (!lc.shaded) continue;  // level 0: the G-buffer the upsampling is guided by
    const int w = levelExtent(c.width, lc.scale), h = levelExtent(c.height, lc.scale);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        ml.stencil.at(x, y) = 1;
        ml.alpha.at(x, y) = 1.0f;
      }
  }
  return levels;
}

BlendResult BlendResult::allocate(const Constants& c, int channels, bool keepStages) {
  BlendResult r;
  const int w = c.width, h = c.height;
  r.levelMap = ImageU8::uninitialised(w, h);
  r.final = ImageF::uninitialised(w, h, channels);
  if (keepStages)
    for (int l = 0; l < kLevelCount; ++l) {
      if (!c.levels[static_cast<size_t>(l)].enabled) continue;
      r.upsampled[static_cast<size_t>(l)] = ImageF(w, h, channels);
      r.alpha[static_cast<size_t>(l)] = ImageF(w, h, 1);
      r.composite[static_cast<size_t>(l)] = ImageF(w, h, channels);
    }
  return r;
}

void FrameResult::countShadedPixels() {
  shadedPixelsTotal = 0;
  int64_t blockTotal = 0;
  for (int l = 0; l < kLevelCount; ++l) {
    LevelResult& lr = levels[static_cast<size_t>(l)];
    lr.shadedPixels = lr.shadedBlockPixels = 0;
    if (!constants.levels[static_cast<size_t>(l)].enabled) continue;
    const ImageU8& s = lr.masks.stencil;
    // Per pair of rows (one row of 4×2 blocks): its set pixels and its blocks holding any;
    // integer sums, so the total is the same for any thread count.
    const int blockRows = (s.height + 1) / 2;
    std::vector<int64_t> setPixels(static_cast<size_t>(blockRows)), blockPixels(static_cast<size_t>(blockRows));
    parallelFor(0, blockRows, [&](int by) {
      const uint8_t* top = &s.at(0, 2 * by);
      const uint8_t* bottom = 2 * by + 1 < s.height ? &s.at(0, 2 * by + 1) : nullptr;
      int64_t set = 0, blocks = 0;
      for (int bx = 0; bx < s.width; bx += 4) {
        uint8_t any = 0;
        for (int x = bx; x < std::min(bx + 4, s.width); ++x) {
          set += top[x] + (bottom ? bottom[x] : 0);
          any |= top[x] | (bottom ? bottom[x] : 0);
        }
        blocks += any ? 8 : 0;
      }
      setPixels[static_cast<size_t>(by)] = set;
      blockPixels[static_cast<size_t>(by)] = blocks;
    });
    for (int by = 0; by < blockRows; ++by) {
      lr.shadedPixels += setPixels[static_cast<size_t>(by)];
      lr.shadedBlockPixels += blockPixels[static_cast<size_t>(by)];
    }
    shadedPixelsTotal += lr.shadedPixels;
    blockTotal += lr.shadedBlockPixels;
  }
  const double pixels = static_cast<double>(constants.width) * constants.height;
  idealSpeedup = pixels / static_cast<double>(std::max<int64_t>(shadedPixelsTotal, 1));
  blockIdealSpeedup = pixels / static_cast<double>(std::max<int64_t>(blockTotal, 1));
}

namespace {
// What a full-res pixel on geometry pays by the sample: the search at least, without one.
uint8_t paysAt(const ImageU8& pcf, int x, int y) { return pcf.empty() ? kPcfSampleSearch : pcfSampleValue(pcf, x, y); }
}  // namespace

void countHits(FrameCounts& n, const ImageU8& hit, const ImageU8& pcf, const Constants& c, ImageU8* silhouetteBlocks) {
  n.hitPixels = n.searchedPixels = n.pcfPixels = n.searchedFootprint = 0;
  n.silhouette = {};
  const int w = std::min(c.width, hit.width), h = std::min(c.height, hit.height);
  if (w <= 0 || h <= 0) return;
  // 1. Per row, in parallel (integer sums per row, so the totals are the same for any thread
  // count): H, H_a, H_p, and the silhouette pixels (edgeAt's background edge: on geometry, with a
  // 4-neighbour inside the image off it) into `marks[0]`.
  std::array<ImageU8, kLevelCount> marks;
  marks[0] = ImageU8::uninitialised(w, h);
  std::vector<std::array<int64_t, 5>> rows(static_cast<size_t>(h));  // H, H_a, H_p, B_0, F
  parallelFor(0, h, [&](int y) {
    const uint8_t* mid = &hit.at(0, y);
    // a 4-neighbour outside the image is no edge: the pixel itself stands in for it
    const uint8_t* up = y > 0 ? &hit.at(0, y - 1) : mid;
    const uint8_t* down = y + 1 < hit.height ? &hit.at(0, y + 1) : mid;
    uint8_t* out = &marks[0].at(0, y);
    auto silhouetteAt = [&](int x, int left, int right) {
      return static_cast<uint8_t>((mid[x] != 0) & ((mid[left] == 0) | (mid[right] == 0) | (up[x] == 0) | (down[x] == 0)));
    };
    std::array<int64_t, 5> r{};
    // branch-free over the row's inside, so the compiler vectorises it; its two ends clamp
    const int inner = std::min(w, hit.width - 1);
    if (w > 0) out[0] = silhouetteAt(0, 0, std::min(1, hit.width - 1));
    for (int x = 1; x < inner; ++x) out[x] = silhouetteAt(x, x - 1, x + 1);
    for (int x = std::max(inner, 1); x < w; ++x) out[x] = silhouetteAt(x, x - 1, std::min(x + 1, hit.width - 1));
    for (int x = 0; x < w; ++x) {
      r[0] += mid[x] != 0;
      r[3] += out[x];
    }
    // H_a, H_p: a pixel on geometry pays what its 8×8 block's sample says. Without a sample every
    // one searches: H_a = H, at once (one loop over the row's runs for both cases took 0.56 ms at
    // 720p against 0.38; NeverSlower.CountHitsIsItsDefinitionOnRandomImages checks both).
    if (pcf.empty()) {
      r[1] = r[0];
    } else {
      for (int x0 = 0; x0 < w; x0 += kPcfSampleStep) {
        int64_t hits = 0;
        for (int x = x0; x < std::min(x0 + kPcfSampleStep, w); ++x) hits += mid[x] != 0;
        const uint8_t pays = paysAt(pcf, x0, y), paid = pcfSampleClass(pays);
        r[1] += paid != kPcfSampleNone ? hits : 0;
        r[2] += paid == kPcfSamplePcf ? hits : 0;
        r[4] += paid != kPcfSampleNone ? hits * pcfSampleFootprintSteps(pays) : 0;  // F: the block's pixels at its sample's
      }
    }
    rows[static_cast<size_t>(y)] = r;
  });
  for (const auto& r : rows) {
    n.hitPixels += r[0];
    n.searchedPixels += r[1];
    n.pcfPixels += r[2];
    n.silhouette[0] += r[3];
    n.searchedFootprint += r[4];
  }
  // 2. B_ℓ: level ℓ's marks are the 2×2 OR of level ℓ−1's (a level-ℓ pixel whose 2^ℓ block holds a
  // silhouette pixel), counted at every enabled level.
  for (int l = 1; l < kLevelCount; ++l) {
    const ImageU8& finer = marks[static_cast<size_t>(l - 1)];
    ImageU8& m = marks[static_cast<size_t>(l)];
    m = ImageU8::uninitialised((finer.width + 1) / 2, (finer.height + 1) / 2);
    std::vector<int64_t> counts(static_cast<size_t>(m.height), 0);
    parallelFor(0, m.height, [&](int y) {
      const uint8_t* a = &finer.at(0, 2 * y);
      const uint8_t* b = 2 * y + 1 < finer.height ? &finer.at(0, 2 * y + 1) : a;
      uint8_t* out = &m.at(0, y);
      int64_t count = 0;
      for (int x = 0; x < m.width; ++x) {
        const int x1 = std::min(2 * x + 1, finer.width - 1);
        out[x] = a[2 * x] | a[x1] | b[2 * x] | b[x1];
        count += out[x];
      }
      counts[static_cast<size_t>(y)] = count;
    });
    if (c.levels[static_cast<size_t>(l)].enabled)
      for (int64_t v : counts) n.silhouette[static_cast<size_t>(l)] += v;
  }
  static_assert(1 << (kLevelCount - 1) == kEdgeSampleStep, "the coarsest level's blocks are the edge sample's");
  if (silhouetteBlocks) *silhouetteBlocks = std::move(marks[kLevelCount - 1]);
}

ImageU8 nearBlocks(const ImageU8& blocks, int blockSize, int radius, int radiusY) {
  // the blocks within ceil(r / B) blocks of a set block, across and down: a separable box max
  const int d = (radius + blockSize - 1) / blockSize;
  const int dy = ((radiusY < 0 ? radius : radiusY) + blockSize - 1) / blockSize;
  const int w = blocks.width, h = blocks.height;
  ImageU8 rows(w, h), near(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t m = 0;
      for (int i = std::max(x - d, 0); i <= std::min(x + d, w - 1); ++i) m |= blocks.at(i, y);
      rows.at(x, y) = m;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      uint8_t m = 0;
      for (int j = std::max(y - dy, 0); j <= std::min(y + dy, h - 1); ++j) m |= rows.at(x, j);
      near.at(x, y) = m;
    }
  return near;
}

void countEdgeSample(FrameCounts& n, const ImageU8& sample, const ImageU8& silhouetteBlocks, const ImageU8& hit,
                     const Constants& c) {
  n.edgeBlocks = 0;
  n.reach = n.reachHits = {};
  if (sample.empty()) return;
  // 1. The blocks the reach starts from: a sampled edge or a silhouette pixel (the sample's
  // diagonal can miss a one-pixel silhouette at 45°; the silhouettes are counted exactly).
  ImageU8 blocks = sample;
  for (int y = 0; y < std::min(blocks.height, silhouetteBlocks.height); ++y)
    for (int x = 0; x < std::min(blocks.width, silhouetteBlocks.width); ++x) blocks.at(x, y) |= silhouetteBlocks.at(x, y);
  for (uint8_t v : blocks.data) n.edgeBlocks += v != 0;
  // 2. The full-res pixels on geometry in each block, a block's row of 8 flags at a time (each
  // byte folded to its low bit, so any non-zero flag counts once).
  static_assert(kEdgeSampleStep == 8, "a block's row is one 64-bit word of flags");
  std::vector<int64_t> blockHits(blocks.data.size(), 0);
  const int w = std::min(hit.width, blocks.width * kEdgeSampleStep);
  parallelFor(0, blocks.height, [&](int by) {
    int64_t* row = &blockHits[static_cast<size_t>(by) * static_cast<size_t>(blocks.width)];
    for (int y = by * kEdgeSampleStep; y < std::min(hit.height, (by + 1) * kEdgeSampleStep); ++y) {
      const uint8_t* h = &hit.at(0, y);
      int x = 0;
      for (; x + kEdgeSampleStep <= w; x += kEdgeSampleStep) {
        uint64_t flags;
        std::memcpy(&flags, h + x, sizeof flags);
        flags |= flags >> 4;
        flags |= flags >> 2;
        flags |= flags >> 1;
        row[x / kEdgeSampleStep] += std::popcount(flags & 0x0101010101010101ull);
      }
      for (; x < w; ++x) row[x / kEdgeSampleStep] += h[x] != 0;
    }
  });
  // 3. Per shaded level below the coarsest, finest first: the blocks within r_ℓ of a block from
  // step 1, OR the finer level's (the closure puts every finer S into the coarser ones).
  ImageU8 reach(blocks.width, blocks.height);
  for (const LevelConstants& lc : c.levels) {
    if (lc.index >= c.coarsestEnabled) break;
    const int blockSize = std::max(1, kEdgeSampleStep / lc.scale);  // level-ℓ pixels per block side
    const ImageU8 near = nearBlocks(blocks, blockSize, lc.blurRadius);
    for (size_t i = 0; i < reach.data.size(); ++i) reach.data[i] |= near.data[i];
    if (!lc.enabled || !lc.shaded) continue;
    const auto l = static_cast<size_t>(lc.index);
    for (size_t i = 0; i < reach.data.size(); ++i)
      if (reach.data[i]) {
        n.reach[l] += static_cast<int64_t>(blockSize) * blockSize;
        n.reachHits[l] += blockHits[i];
      }
  }
}

namespace {
// |S_ℓ|, |S_ℓ ∩ hit|, |S_ℓ ∩ hit ∩ searched| and |S_ℓ ∩ hit ∩ pcf| per shaded level (H, H_a and
// H_p are countHits').
void countStencils(FrameCounts& n, const std::array<const ImageU8*, kLevelCount>& stencils, const Constants& c,
                   const ImageU8& hit, const ImageU8& pcf) {
  for (int l = 0; l < kLevelCount; ++l) {
    const auto i = static_cast<size_t>(l);
    n.shaded[i] = n.shadedHit[i] = n.shadedSearched[i] = n.shadedPcf[i] = 0;
    if (!c.levels[i].enabled || !c.levels[i].shaded) continue;
    const ImageU8& s = *stencils[i];
    const int scale = 1 << l;
    // per row, in parallel: integer sums, so the totals are the same for any thread count
    std::vector<std::array<int64_t, 4>> rows(static_cast<size_t>(s.height));  // |S|, ∩ hit, ∩ searched, ∩ pcf
    parallelFor(0, s.height, [&](int y) {
      std::array<int64_t, 4> r{};
      const uint8_t* row = s.width > 0 ? &s.at(0, y) : nullptr;
      for (int x = 0; x < s.width; ++x)
        if (row[x]) {
          ++r[0];
          if (!levelPixelHit(hit, x, y, scale)) continue;
          ++r[1];
          const uint8_t paid = pcfSampleClass(paysAt(pcf, levelSamplePixel(x, scale), levelSamplePixel(y, scale)));
          r[2] += paid != kPcfSampleNone;
          r[3] += paid == kPcfSamplePcf;
        }
      rows[static_cast<size_t>(y)] = r;
    });
    for (const auto& r : rows) {
      n.shaded[i] += r[0];
      n.shadedHit[i] += r[1];
      n.shadedSearched[i] += r[2];
      n.shadedPcf[i] += r[3];
    }
  }
}
}  // namespace

void countForRule(FrameCounts& n, const Masks& masks, const Constants& c, const ImageU8& hit, const ImageU8& pcf) {
  countStencils(n, {&masks[0].stencil, &masks[1].stencil, &masks[2].stencil, &masks[3].stencil}, c, hit, pcf);
}

void FrameResult::countHitPixels(const ImageU8& hit) {
  if (hit.empty()) return;
  FrameCounts n;
  countHits(n, hit, ImageU8(), constants);
  countStencils(n, {&levels[0].masks.stencil, &levels[1].masks.stencil, &levels[2].masks.stencil, &levels[3].masks.stencil},
                constants, hit, ImageU8());
  int64_t shadedOnGeometry = 0;
  for (int64_t v : n.shadedHit) shadedOnGeometry += v;
  idealSpeedupHit =
      static_cast<double>(std::max<int64_t>(n.hitPixels, 1)) / static_cast<double>(std::max<int64_t>(shadedOnGeometry, 1));
}

std::array<LevelImages, kLevelCount> FrameResult::blendInputs() const {
  std::array<LevelImages, kLevelCount> in;
  for (size_t l = 0; l < in.size(); ++l) in[l] = {&levels[l].sub, &levels[l].masks.stencil, &levels[l].masks.alpha};
  return in;
}

double FrameResult::timing(const std::string& stage) const {
  double ms = 0.0;
  for (const StageTiming& t : timings)
    if (t.stage == stage) ms += t.ms;
  return ms;
}

bool applyNeverSlower(FrameResult& f, const CostModel& model) {
  f.fallback = decideFallback(model, f.constants, f.counts);
  f.fallback.evaluated = f.constants.neverSlower;
  f.fallback.wouldFallBack = f.fallback.fellBack;
  if (!f.constants.neverSlower) f.fallback.fellBack = false;  // predicted only
  if (!f.fallback.fellBack) return false;
  f.constants.fallBackToFull();
  return true;
}

void applyNeverSlower(FrameResult& f, Masks& masks, const CostModel& model) {
  if (applyNeverSlower(f, model)) masks = fullModeMasks(f.constants);
}

int64_t estimateFrameBytes(const Constants& c, bool keepStages) {
  const int64_t channels = c.channels();
  int64_t bytes = 0;
  for (const LevelConstants& lc : c.levels) {
    if (!lc.enabled) continue;
    const int64_t pixels = static_cast<int64_t>(lc.width) * lc.height;
    int64_t perPixel = 4 + 12 + 12 + 12 + 1;  // G-buffer: depth, position, normal, albedo, hit
    perPixel += 1 + 4 + 1;                    // M_ℓ, a_ℓ, S_ℓ
    perPixel += 2 * 4 * channels;             // raw and blurred sub-image
    if (c.effect == Effect::Ssao) perPixel += 16;  // occluder planes
    if (c.effect == Effect::Ssgi) perPixel += 12;  // direct light
    bytes += pixels * perPixel;
  }
  const int64_t padded = static_cast<int64_t>(c.paddedWidth) * c.paddedHeight;
  const int64_t pixels = static_cast<int64_t>(c.width) * c.height;
  bytes += padded * 5;                            // edge kinds and E
  bytes += pixels * (4 * channels + 1 + 12 + 1);  // final, level map, shaded, one-tap shadow test
  if (keepStages) bytes += pixels * kLevelCount * (8 * channels + 4);  // ĉ_ℓ, c'_ℓ, α_ℓ
  if (c.needsShadowMap()) bytes += static_cast<int64_t>(c.ssm.shadowMapSize) * c.ssm.shadowMapSize * 4;
  bytes += pixels * 12;  // the largest image being written (an 8-bit or float copy of it)
  return bytes;
}

View previousView(const Constants& c, const View& current) {
  if (c.foveation.panned) {  // SPEC §13 step 3: the camera panned by `pan` along its right axis since
    View prev = current;
    prev.eye = current.eye - c.foveation.pan * current.right;
    return prev;
  }
  Camera prev;
  prev.eye = c.foveation.prevEye;
  prev.target = c.foveation.prevTarget;
  prev.up = c.foveation.prevUp;
  prev.yfov = c.foveation.prevYfov;
  return makeView(prev, c.width, c.height, c.paddedWidth, c.paddedHeight);
}

void limitTileRates(ImageU8& rates, const ImageU8& limit) {
  for (int ty = 0; ty < rates.height; ++ty)
    for (int tx = 0; tx < rates.width; ++tx) {
      const int px = std::min(tx * kTileSize + kTileSize / 2, limit.width - 1);
      const int py = std::min(ty * kTileSize + kTileSize / 2, limit.height - 1);
      const uint8_t eye = std::min<uint8_t>(2, limit.at(px, py, kLimitLevel));
      rates.at(tx, ty) = std::max(rates.at(tx, ty), eye);
    }
}

}  // namespace mrr
