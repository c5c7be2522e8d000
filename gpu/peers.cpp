#include "gpu/peers.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <functional>
#include <memory>
#include <vector>

#include "gpu/program.h"

namespace mrr::gpu {

namespace {
// The level-ℓ pixels whose s_ℓ×s_ℓ block starts inside the W×H image (as cpu_ref/peers.cpp).
int levelExtent(int fullExtent, int scale) { return (fullExtent + scale - 1) / scale; }


// A small integer (a rate, a level, a 0/1 flag) stored in a float channel.
uint8_t toLevel(float v) { return static_cast<uint8_t>(v + 0.5f); }

// One tiles step into a fresh single-target framebuffer of the given size.
Target tileStep(const GpuScene& scene, int step, int width, int height, unsigned source,
                                      const std::function<void(unsigned)>& setUniforms = {}, int sourceChannel = 0) {
  const unsigned program = scene.program("peers.tiles", "fullscreen.vert", "peers.frag", "#define TILE_MASKS\n");
  Target target = scene.target(width, height, 1, false);
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

ImageU8 tileRates(const GpuScene& scene, unsigned edges, int edgeChannel, int width, int height) {
  const int tw = (width + kTileSize - 1) / kTileSize, th = (height + kTileSize - 1) / kTileSize;
  // 1. a tile holds an edge: max over its 16×16 pixels of E
  const auto hasEdge = tileStep(scene, 1, tw, th, edges, {}, edgeChannel);
  // 2. rate 0 on edge tiles, 1 beside one (8-neighbourhood), 2 elsewhere
  const auto rate = tileStep(scene, 2, tw, th, hasEdge->texture(0));
  const ImageF read = rate->read(0, 1);
  ImageU8 rates(tw, th);
  for (size_t i = 0; i < rates.data.size(); ++i) rates.data[i] = toLevel(read.data[i]);
  return rates;
}

std::array<MaskLevel, kLevelCount> tileMasks(const GpuScene& scene, const ImageU8& rates, const Constants& c) {
  const unsigned rateTexture = uploadTexture(toFloat(rates));
  std::array<MaskLevel, kLevelCount> levels;
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    // 3. M_ℓ = rate, S_ℓ = a_ℓ = [rate == ℓ, inside W×H] (r, g, b of one target)
    const auto target = tileStep(scene, 3, lc.width, lc.height, rateTexture, [&](unsigned program) {
      glUniform1i(uniform(program, "level"), l);
      glUniform1i(uniform(program, "perTile"), kTileSize / lc.scale);
      glUniform2i(uniform(program, "extent"), levelExtent(c.width, lc.scale),
                  levelExtent(c.height, lc.scale));
    });
    const ImageF read = target->read(0, 3);
    MaskLevel& ml = levels[static_cast<size_t>(l)];
    ml.mask = ImageU8(lc.width, lc.height);
    ml.stencil = ImageU8(lc.width, lc.height);
    ml.alpha = ImageF(lc.width, lc.height);
    for (size_t i = 0; i < ml.mask.data.size(); ++i) {
      ml.mask.data[i] = toLevel(read.data[3 * i]);
      ml.stencil.data[i] = toLevel(read.data[3 * i + 1]);
      ml.alpha.data[i] = read.data[3 * i + 2];
    }
  }
  glDeleteTextures(1, &rateTexture);
  return levels;
}

BlendResult composePeer(const GpuScene& scene, const std::array<unsigned, kLevelCount>& subs, int channels,
                        const std::array<const Framebuffer*, kLevelCount>& gbuffers, const ImageU8& rates,
                        const Constants& c, bool keepStages, GpuImage* finalOnGpu) {
  const MethodInfo& method = methodInfo(c.mode);  // uniform-k: its level k, joint-bilateral upsampled
  const bool uniformK = method.compose == Compose::JointBilateral;
  const int k = uniformK ? method.finestShadedLevel() : 0;
  // The composition: the final value and the level it came from, at full res.
  Target composedTarget = scene.target(c.width, c.height, 2, false);
  const Framebuffer& composed = *composedTarget;
  std::vector<unsigned> uploaded;
  auto upload = [&](const ImageF& image) {
    uploaded.push_back(uploadTexture(image));
    return uploaded.back();
  };
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
    bindTextures(program, {{"rates", upload(toFloat(rates))},
                           {"sub0", subs[0]},
                           {"sub1", subs[1]},
                           {"sub2", subs[2]}});
  }
  scene.drawFullscreen();
  checkGl("blend");
  BlendResult r;
  r.final = composed.read(0, channels);
  const ImageF levelMap = composed.read(1, 1);
  r.levelMap = ImageU8(c.width, c.height);
  for (size_t i = 0; i < levelMap.data.size(); ++i) r.levelMap.data[i] = toLevel(levelMap.data[i]);
  // ĉ_ℓ, α_ℓ and c'_ℓ per enabled level, from the composed value and level map.
  if (keepStages) {
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
  }
  glDeleteTextures(static_cast<GLsizei>(uploaded.size()), uploaded.data());
  if (finalOnGpu) *finalOnGpu = {std::move(composedTarget), 0};
  return r;
}

}  // namespace mrr::gpu
