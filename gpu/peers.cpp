#include "gpu/peers.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <functional>
#include <memory>
#include <vector>

#include "gpu/program.h"

namespace mrr::gpu {

namespace {
// A small integer (a rate, a level, a 0/1 flag) stored in a float channel.
uint8_t toLevel(float v) { return static_cast<uint8_t>(v + 0.5f); }

// One tiles step into a fresh single-target framebuffer of the given size and format.
Target tileStep(const GpuScene& scene, int step, int width, int height, unsigned source,
                const std::function<void(unsigned)>& setUniforms = {}, int sourceChannel = 0,
                Texel format = Texel::Rgba32f) {
  const unsigned program = scene.program("peers.tiles", "fullscreen.vert", "peers.frag", "#define TILE_MASKS\n");
  Target target = scene.target(width, height, 1, false, format);
  target->bind();
  glUseProgram(program);
  glUniform1i(uniform(program, "step"), step);
  glUniform1i(uniform(program, "sourceChannel"), sourceChannel);
  if (setUniforms) setUniforms(program);
  bindTextures(program, {{"source", source}});
  scene.drawFullscreen();
  checkGl("masks");
  return target;
}
}  // namespace

Target drawTileRates(const GpuScene& scene, unsigned edges, int edgeChannel, int width, int height, unsigned limit) {
  const int tw = (width + kTileSize - 1) / kTileSize, th = (height + kTileSize - 1) / kTileSize;
  // 1. a tile holds an edge: max over its 16×16 pixels of E
  const auto hasEdge = tileStep(scene, 1, tw, th, edges, {}, edgeChannel);
  // 2. rate 0 on edge tiles, 1 beside one (8-neighbourhood), 2 elsewhere
  Target rate = tileStep(scene, 2, tw, th, hasEdge->texture(0));
  if (!limit) return rate;
  // 4. SPEC §13: no finer than the eye and motion allow at the tile's centre
  return tileStep(scene, 4, tw, th, rate->texture(0), [&](unsigned program) { bindTextures(program, {{"limit", limit}}, 1); });
}

ImageU8 readTileRates(const Framebuffer& rates) {
  const ImageF read = rates.read(0, 1);
  ImageU8 out(read.width, read.height);
  for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = toLevel(read.data[i]);
  return out;
}

std::unique_ptr<MaskTargets> drawTileMasks(const GpuScene& scene, Target rates, const Constants& c) {
  auto out = std::make_unique<MaskTargets>();
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    // 3. S_ℓ = a_ℓ = [rate == ℓ, inside W×H] (r of an R8 target)
    Target& s = out->stencilTarget[static_cast<size_t>(l)];
    s = tileStep(scene, 3, lc.width, lc.height, rates->texture(0), [&](unsigned program) {
      glUniform1i(uniform(program, "level"), l);
      glUniform1i(uniform(program, "perTile"), kTileSize / lc.scale);
      glUniform2i(uniform(program, "extent"), levelExtent(c.width, lc.scale), levelExtent(c.height, lc.scale));
    }, 0, Texel::R8);
    out->stencil[static_cast<size_t>(l)] = out->alpha[static_cast<size_t>(l)] = s->texture(0);  // a_ℓ = S_ℓ
  }
  out->tileRates = std::move(rates);
  return out;
}

std::array<MaskLevel, kLevelCount> readTileMasks(const MaskTargets& masks, const ImageU8& rates, const Constants& c) {
  std::array<MaskLevel, kLevelCount> levels;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    MaskLevel& ml = levels[static_cast<size_t>(l)];
    ml.stencil = masks.stencilTarget[static_cast<size_t>(l)]->readBinary(0);
    ml.mask = ImageU8(lc.width, lc.height);
    ml.alpha = ImageF(lc.width, lc.height);
    const int perTile = kTileSize / lc.scale;
    for (int y = 0; y < lc.height; ++y)
      for (int x = 0; x < lc.width; ++x) {
        ml.mask.at(x, y) = rates.at(std::min(x / perTile, rates.width - 1), std::min(y / perTile, rates.height - 1));
        ml.alpha.at(x, y) = ml.stencil.at(x, y);
      }
  }
  return levels;
}

void readComposed(const Framebuffer& composed, int channels, BlendResult& r) {
  r.final = composed.read(0, channels);
  const ImageF levelMap = composed.read(1, 1);
  r.levelMap = ImageU8(levelMap.width, levelMap.height);
  for (size_t i = 0; i < levelMap.data.size(); ++i) r.levelMap.data[i] = toLevel(levelMap.data[i]);
}

BlendResult composePeer(const GpuScene& scene, const std::array<unsigned, kLevelCount>& subs, int channels,
                        const std::array<const Framebuffer*, kLevelCount>& gbuffers, unsigned rates,
                        const Constants& c, bool keepStages, Target& composedTarget) {
  const MethodInfo& method = methodInfo(c.mode);  // uniform-k: its level k, joint-bilateral upsampled
  const bool uniformK = method.compose == Compose::JointBilateral;
  const int k = uniformK ? method.finestShadedLevel() : 0;
  // The composition: the final value and the level it came from, at full res.
  composedTarget = scene.target(c.width, c.height, 2, false);
  const Framebuffer& composed = *composedTarget;
  composed.bind();
  if (uniformK) {
    const unsigned program = scene.program("peers.uniform", "fullscreen.vert", "peers.frag",
                                           "#define COMPOSE\n#define JOINT_BILATERAL\n");
    glUseProgram(program);
    const Framebuffer& coarse = *gbuffers[static_cast<size_t>(k)];
    const Framebuffer& full = *gbuffers[0];
    bindTextures(program, {{"sub", subs[static_cast<size_t>(k)]},
                           {"coarsePositionHit", coarse.texture(0)},
                           {"coarseNormalDepth", coarse.texture(1)},
                           {"fullPositionHit", full.texture(0)},
                           {"fullNormalDepth", full.texture(1)}});
    glUniform1i(uniform(program, "level"), k);
    glUniform1i(uniform(program, "scale"), c.levels[static_cast<size_t>(k)].scale);
    glUniform1f(uniform(program, "sigmaDepth"), c.bilateral.sigmaDepth);
    glUniform1f(uniform(program, "normalPower"), c.bilateral.normalPower);
  } else {
    const unsigned program =
        scene.program("peers.broadcast", "fullscreen.vert", "peers.frag", "#define COMPOSE\n");
    glUseProgram(program);
    bindTextures(program, {{"rates", rates},
                           {"sub0", subs[0]},
                           {"sub1", subs[1]},
                           {"sub2", subs[2]}});
  }
  scene.drawFullscreen();
  checkGl("blend");
  BlendResult r;
  if (!keepStages) return r;  // on the GPU: the caller reads `composed` when it asks
  readComposed(composed, channels, r);
  // ĉ_ℓ, α_ℓ and c'_ℓ per enabled level, from the composed value and level map.
  const unsigned program =
      scene.program("peers.levels", "fullscreen.vert", "peers.frag", "#define LEVEL_STAGES\n");
  for (int l = 0; l < kLevelCount; ++l) {
    if (!c.levels[static_cast<size_t>(l)].enabled) continue;
    const Target levelTarget = scene.target(c.width, c.height, 3, false);
    const Framebuffer& target = *levelTarget;
    target.bind();
    glUseProgram(program);
    bindTextures(program, {{"composed", composed.texture(0)}, {"levelMap", composed.texture(1)}});
    glUniform1i(uniform(program, "level"), l);
    scene.drawFullscreen();
    checkGl("blend");
    r.upsampled[static_cast<size_t>(l)] = target.read(0, channels);
    r.alpha[static_cast<size_t>(l)] = target.read(1, 1);
    r.composite[static_cast<size_t>(l)] = target.read(2, channels);
  }
  return r;
}

}  // namespace mrr::gpu
