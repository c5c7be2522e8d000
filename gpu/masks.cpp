#include "gpu/masks.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <memory>

#include "common/error.h"
#include "gpu/program.h"

namespace mrr::gpu {

namespace {

constexpr int kMaxTaps = 49;  // matches weights[49] in masks.frag: σ² ≤ 64 gives r ≤ 24

struct Pass {
  const GpuScene& scene;
  unsigned program;
  // One full-screen step into a fresh single-target framebuffer of the given size.
  Target run(int step, Texel format, int width, int height, unsigned source, unsigned previous = 0, int factor = 1,
             glm::ivec2 direction = {1, 0}, const std::vector<float>* weights = nullptr, int sourceChannel = 0) const {
    auto target = std::make_unique<Framebuffer>(width, height, 1, false, format);
    target->bind();
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "step"), step);
    glUniform1i(glGetUniformLocation(program, "sourceChannel"), sourceChannel);
    glUniform1i(glGetUniformLocation(program, "factor"), factor);
    glUniform2i(glGetUniformLocation(program, "direction"), direction.x, direction.y);
    if (weights) {
      require(static_cast<int>(weights->size()) <= kMaxTaps, "gpu: masks: blur kernel larger than 49 taps");
      glUniform1i(glGetUniformLocation(program, "radius"), static_cast<int>(weights->size() / 2));
      glUniform1fv(glGetUniformLocation(program, "weights"), static_cast<GLsizei>(weights->size()), weights->data());
    }
    bindTextures(program, {{"source", source}});
    bindTextures(program, {{"previous", previous ? previous : source}}, 1);
    scene.drawFullscreen();
    checkGl("masks");
    return target;
  }
};

// A target cleared to `value` (the coarsest enabled level's a = S = 1).
Target constantTarget(int width, int height, Texel format, float value) {
  auto target = std::make_unique<Framebuffer>(width, height, 1, false, format);
  target->bind();
  const float v[4] = {value, value, value, value};
  glClearBufferfv(GL_COLOR, 0, v);
  return target;
}

}  // namespace

std::unique_ptr<MaskTargets> drawMasks(const GpuScene& scene, unsigned edges, int edgeChannel, const Constants& c) {
  const Pass pass{scene, scene.program("masks", "fullscreen.vert", "masks.frag")};
  auto out = std::make_unique<MaskTargets>();
  out->drawn = true;
  auto& mask = out->maskTarget;
  auto& stencil = out->stencilTarget;
  // 1. mask pyramid: M_0 = E, M_ℓ = maxpool2(M_{ℓ−1}), through disabled levels too
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const unsigned source = l == 0 ? edges : mask[static_cast<size_t>(l - 1)]->texture(0);
    mask[static_cast<size_t>(l)] = pass.run(1, Texel::R8, lc.width, lc.height, source, 0, l == 0 ? 1 : 2, {1, 0},
                                            nullptr, l == 0 ? edgeChannel : 0);
  }
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const size_t i = static_cast<size_t>(l);
    if (l == c.coarsestEnabled) {  // 2. the coarsest enabled level covers everything
      out->alphaTarget[i] = constantTarget(lc.width, lc.height, Texel::R32f, 1.0f);
      stencil[i] = constantTarget(lc.width, lc.height, Texel::R8, 1.0f);
      continue;
    }
    // 2. a_ℓ = G(σ²) ∗ M_ℓ, separable; 3. S_ℓ = [a_ℓ > 0]
    const auto horizontal =
        pass.run(2, Texel::R32f, lc.width, lc.height, mask[i]->texture(0), 0, 1, {1, 0}, &lc.gaussian);
    out->alphaTarget[i] = pass.run(2, Texel::R32f, lc.width, lc.height, horizontal->texture(0), 0, 1, {0, 1}, &lc.gaussian);
    stencil[i] = pass.run(3, Texel::R8, lc.width, lc.height, out->alphaTarget[i]->texture(0));
  }
  // 4. coverage closure, fine to coarse, across disabled levels
  for (int l = 0; l < kLevelCount; ++l) {
    const int next = c.nextCoarserEnabled(l);
    if (!c.levels[static_cast<size_t>(l)].enabled || next < 0) continue;
    const LevelConstants& ln = c.levels[static_cast<size_t>(next)];
    if (next == c.coarsestEnabled) continue;  // already all 1
    stencil[static_cast<size_t>(next)] =
        pass.run(4, Texel::R8, ln.width, ln.height, stencil[static_cast<size_t>(l)]->texture(0),
                 stencil[static_cast<size_t>(next)]->texture(0), 1 << (next - l));
  }
  for (size_t l = 0; l < kLevelCount; ++l)
    if (c.levels[l].enabled) {
      out->alpha[l] = out->alphaTarget[l]->texture(0);
      out->stencil[l] = stencil[l]->texture(0);
    }
  return out;
}

std::array<MaskLevel, kLevelCount> readMasks(const MaskTargets& masks, const Constants& c, bool stencilsOnly) {
  std::array<MaskLevel, kLevelCount> out;
  for (size_t l = 0; l < kLevelCount; ++l) {
    if (!stencilsOnly) out[l].mask = masks.maskTarget[l]->readBinary(0);  // M_ℓ through disabled levels too
    if (!c.levels[l].enabled) continue;
    out[l].stencil = masks.stencilTarget[l]->readBinary(0);
    if (!stencilsOnly) out[l].alpha = masks.alphaTarget[l]->read(0, 1);
  }
  return out;
}

std::unique_ptr<MaskTargets> uploadMasks(const std::array<MaskLevel, kLevelCount>& masks, const Constants& c) {
  auto out = std::make_unique<MaskTargets>();
  for (size_t l = 0; l < kLevelCount; ++l) {
    if (!c.levels[l].enabled) continue;
    out->stencil[l] = out->uploaded.add(uploadBinary(masks[l].stencil));
    out->alpha[l] = out->uploaded.add(uploadTexture(masks[l].alpha));
  }
  return out;
}

std::array<MaskLevel, kLevelCount> buildMasks(const GpuScene& scene, const ImageU8& edges, const Constants& c) {
  TextureSet uploaded;
  const auto masks = drawMasks(scene, uploaded.add(uploadBinary(edges)), 0, c);
  return readMasks(*masks, c, false);
}

}  // namespace mrr::gpu
