#include "gpu/rule.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <string>

#include "gpu/counts.h"
#include "gpu/program.h"

namespace mrr::gpu {

namespace {
constexpr int kBlock = kEdgeSampleStep;  // rule.frag's blocks: 8×8 full-res pixels, the coarsest level's
static_assert(kBlock == 8 && kPcfSampleStep == 8 && kLevelCount == 4, "rule.frag is written for 8×8 blocks, levels 0–3");

// A rule.frag pass over the per-block grid of the padded full-res grid (width × height blocks).
Target rulePass(const GpuScene& scene, int step, bool withPcf, int targets, int width, int height,
                const std::function<void(unsigned)>& setInputs, int level = -1, bool withSample = false,
                bool withHitBits = false, bool shadowEdges = false) {
  const std::string defines = (level >= 0 ? "#define LEVEL " + std::to_string(level) + "\n" : "") +
                              "#define WITH_SAMPLE " + (withSample ? "1" : "0") + "\n#define WITH_HIT_BITS " +
                              (withHitBits ? "1" : "0") + "\n" + (shadowEdges ? "#define SHADOW_EDGES\n" : "");
  const unsigned program = scene.program("rule." + std::to_string(step) + (withPcf ? ".pcf" : "") +
                                             (withSample ? ".sample" : "") + (shadowEdges ? ".shadow" : "") +
                                             (withHitBits ? ".bits" : "") + (level >= 0 ? ".L" + std::to_string(level) : ""),
                                         "fullscreen.vert", "rule.frag",
                                         "#define STEP " + std::to_string(step) + "\n#define WITH_PCF " +
                                             (withPcf ? "1" : "0") + "\n" + defines);
  Target target = scene.target(width, height, std::vector<Texel>(static_cast<size_t>(targets), Texel::Rgba32ui), false);
  target->bind();
  glUseProgram(program);
  setInputs(program);
  scene.drawFullscreen();
  checkGl("rule");
  return target;
}

// STEP 1 (countHits' counts per block; with the edge sample, Ê per block too).
Target drawHits(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned pcfSample, const EdgeSampleInputs& sample,
                const Constants& c) {
  const bool withSample = sample.settings != nullptr;
  return rulePass(scene, 1, pcfSample != 0, 3, gbuffer0.width() / kBlock, gbuffer0.height() / kBlock, [&](unsigned p) {
    bindTextures(p, {{"normalDepth", gbuffer0.texture(1)}});
    int unit = 1;
    if (pcfSample) bindTextures(p, {{"pcfSample", pcfSample}}, unit++);
    if (withSample) {
      glUniform1f(uniform(p, "normalThreshold"), sample.settings->normalThreshold);
      glUniform1f(uniform(p, "depthThreshold"), sample.settings->depthThreshold);
      if (sample.shadowLit) bindTextures(p, {{"shadowLit", sample.shadowLit}}, unit++);
    }
    glUniform2i(uniform(p, "frame"), c.width, c.height);
  }, -1, withSample, false, withSample && sample.shadowLit != 0);
}

// H, H_a, H_p, F and B_ℓ from STEP 1's sums (values[first..first+8)), as countHits sets them.
void takeHits(const std::vector<int64_t>& v, size_t first, const Constants& c, FrameCounts& n) {
  n.hitPixels = v[first + 0];
  n.searchedPixels = v[first + 1];
  n.pcfPixels = v[first + 2];
  n.searchedFootprint = v[first + 3];
  for (int l = 0; l < kLevelCount; ++l)  // B_0 always, B_ℓ at the enabled levels
    n.silhouette[static_cast<size_t>(l)] = l == 0 || c.levels[static_cast<size_t>(l)].enabled ? v[first + 4 + static_cast<size_t>(l)] : 0;
}
}  // namespace

bool countEarly(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned pcfSample, const EdgeSampleInputs& sample,
                const Constants& c, FrameCounts& n, const std::function<bool(const FrameCounts&)>& wantSample,
                Target* hitBits) {
  n.hitPixels = n.searchedPixels = n.pcfPixels = n.searchedFootprint = 0;
  n.silhouette = {};
  n.edgeBlocks = 0;
  n.reach = n.reachHits = {};
  CountBatch batch(scene);
  Target hits = drawHits(scene, gbuffer0, pcfSample, sample, c);
  const unsigned hitsPerBlock = hits->texture(2);
  Target reach;
  const bool sampled = sample.settings != nullptr;
  if (sampled) {
    // R_ℓ: the union of the boxes of every level ℓ' ≤ ℓ below the coarsest enabled one, each
    // ceil(r_ℓ' / b_ℓ') blocks (nearBlocks), b_ℓ' = 8 / s_ℓ' its pixels per block side
    int reachBlocks[3] = {-1, -1, -1};
    int widest = -1;
    for (const LevelConstants& lc : c.levels) {
      if (lc.index >= c.coarsestEnabled || lc.index >= 3) break;
      const int blockSize = std::max(1, kBlock / lc.scale);
      widest = std::max(widest, (lc.blurRadius + blockSize - 1) / blockSize);
      if (lc.enabled && lc.shaded) reachBlocks[lc.index] = widest;
    }
    reach = rulePass(scene, 2, false, 2, gbuffer0.width() / kBlock, gbuffer0.height() / kBlock, [&](unsigned p) {
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, hitsPerBlock);
      glUniform1i(uniform(p, "hits"), 0);
      glUniform3i(uniform(p, "reachBlocks"), reachBlocks[0], reachBlocks[1], reachBlocks[2]);
    });
  }
  const size_t hitsAt = batch.add(std::move(hits));
  const size_t reachAt = reach ? batch.add(std::move(reach)) : 0;
  const std::vector<int64_t> v = batch.read();
  if (hitBits) *hitBits = batch.take(0);  // step 1's targets: counts2 holds each block's hit bits
  takeHits(v, hitsAt, c, n);
  if (!sampled || !wantSample || !wantSample(n)) return false;
  n.edgeBlocks = v[reachAt];
  for (const LevelConstants& lc : c.levels) {
    if (lc.index >= c.coarsestEnabled || lc.index >= 3) break;
    if (!lc.enabled || !lc.shaded) continue;
    const auto l = static_cast<size_t>(lc.index);
    const int64_t blockSize = std::max(1, kBlock / lc.scale);
    n.reach[l] = v[reachAt + 1 + l] * blockSize * blockSize;
    n.reachHits[l] = v[reachAt + 4 + l];
  }
  return true;
}

namespace {
// countStencils' pass (rule.frag step 3), queued in `batch`; takeStencilCounts reads its sums.
size_t addStencilCounts(CountBatch& batch, const GpuScene& scene, const Framebuffer& gbuffer0, unsigned pcfSample,
                        const std::array<unsigned, kLevelCount>& stencils, const Constants& c, unsigned hitBits) {
  int levelCounted[kLevelCount] = {};
  unsigned any = 0;
  for (size_t l = 0; l < kLevelCount; ++l) {
    levelCounted[l] = c.levels[l].enabled && c.levels[l].shaded && stencils[l] ? 1 : 0;
    if (stencils[l]) any = stencils[l];
  }
  return batch.add(rulePass(scene, 3, pcfSample != 0, 4, gbuffer0.width() / kBlock, gbuffer0.height() / kBlock,
                            [&](unsigned p) {
                              // the hit of each level pixel's sample: step 1's bits, else level 0's G-buffer
                              if (hitBits)
                                bindTextures(p, {{"hitBits", hitBits}});
                              else
                                bindTextures(p, {{"normalDepth", gbuffer0.texture(1)}});
                              int unit = 1;
                              if (pcfSample) bindTextures(p, {{"pcfSample", pcfSample}}, unit++);
                              for (int l = 0; l < kLevelCount; ++l) {
                                const std::string name = "stencil" + std::to_string(l);
                                // a disabled level's sampler is never read: any texture
                                const unsigned t = stencils[static_cast<size_t>(l)];
                                bindTextures(p, {{name.c_str(), t ? t : any}}, unit++);
                              }
                              glUniform4i(uniform(p, "counted"), levelCounted[0], levelCounted[1], levelCounted[2], levelCounted[3]);
                            },
                            -1, false, hitBits != 0));
}
void takeStencilCounts(const std::vector<int64_t>& v, size_t at, FrameCounts& n) {
  for (size_t l = 0; l < kLevelCount; ++l) {
    n.shaded[l] = v[at + 4 * l + 0];
    n.shadedHit[l] = v[at + 4 * l + 1];
    n.shadedSearched[l] = v[at + 4 * l + 2];
    n.shadedPcf[l] = v[at + 4 * l + 3];
  }
}
}  // namespace

void countStencils(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned pcfSample,
                   const std::array<unsigned, kLevelCount>& stencils, const Constants& c, FrameCounts& n,
                   unsigned hitBits) {
  CountBatch batch(scene);
  const size_t at = addStencilCounts(batch, scene, gbuffer0, pcfSample, stencils, c, hitBits);
  takeStencilCounts(batch.read(), at, n);
}

void countShaded(const GpuScene& scene, const Framebuffer& gbuffer0, const std::array<unsigned, kLevelCount>& stencils,
                 FrameResult& f, int64_t hitPixels, FrameCounts* finalCounts, unsigned pcfSample, unsigned hitBits) {
  const Constants& c = f.constants;
  CountBatch batch(scene);
  // H and the final stencils' counts do not fit one batch beside |S_ℓ|'s: then a read of their own
  if (finalCounts && hitPixels < 0) countStencils(scene, gbuffer0, pcfSample, stencils, c, *finalCounts, hitBits);
  const bool together = finalCounts && hitPixels >= 0;
  const size_t finalAt = together ? addStencilCounts(batch, scene, gbuffer0, pcfSample, stencils, c, hitBits) : 0;
  const size_t hitsAt = hitPixels < 0 ? batch.add(drawHits(scene, gbuffer0, 0, {}, c)) : 0;  // H, unless known
  std::array<size_t, kLevelCount> at{};
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled || !stencils[static_cast<size_t>(l)]) continue;
    at[static_cast<size_t>(l)] = batch.add(rulePass(scene, 4, false, 1, (lc.width + 3) / 4, (lc.height + 1) / 2,
                                                    [&](unsigned p) {
                                                      bindTextures(p, {{"normalDepth", gbuffer0.texture(1)},
                                                                       {"stencil", stencils[static_cast<size_t>(l)]}});
                                                    },
                                                    l));
  }
  const std::vector<int64_t> v = batch.read();
  if (together) takeStencilCounts(v, finalAt, *finalCounts);
  f.shadedPixelsTotal = 0;
  int64_t blockTotal = 0, shadedOnGeometry = 0;
  for (int l = 0; l < kLevelCount; ++l) {
    LevelResult& lr = f.levels[static_cast<size_t>(l)];
    lr.shadedPixels = lr.shadedBlockPixels = 0;
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled || !stencils[static_cast<size_t>(l)]) continue;
    const size_t i = at[static_cast<size_t>(l)];
    lr.shadedPixels = v[i];
    lr.shadedBlockPixels = 8 * v[i + 1];
    f.shadedPixelsTotal += lr.shadedPixels;
    blockTotal += lr.shadedBlockPixels;
    if (lc.shaded) shadedOnGeometry += v[i + 2];
  }
  const double pixels = static_cast<double>(c.width) * c.height;
  f.idealSpeedup = pixels / static_cast<double>(std::max<int64_t>(f.shadedPixelsTotal, 1));
  f.blockIdealSpeedup = pixels / static_cast<double>(std::max<int64_t>(blockTotal, 1));
  f.idealSpeedupHit = static_cast<double>(std::max<int64_t>(hitPixels < 0 ? v[hitsAt] : hitPixels, 1)) /
                      static_cast<double>(std::max<int64_t>(shadedOnGeometry, 1));
}

}  // namespace mrr::gpu
