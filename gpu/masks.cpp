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
  std::unique_ptr<Framebuffer> run(int step, int width, int height, unsigned source, unsigned previous = 0,
                                   int factor = 1, glm::ivec2 direction = {1, 0},
                                   const std::vector<float>* weights = nullptr) const {
    auto target = std::make_unique<Framebuffer>(width, height, 1, false);
    target->bind();
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "step"), step);
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

ImageU8 toMask(const ImageF& f) {
  ImageU8 out(f.width, f.height);
  for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = f.data[i] > 0.5f;
  return out;
}

}  // namespace

std::array<MaskLevel, kLevelCount> buildMasks(const GpuScene& scene, const ImageU8& edges, const Constants& c) {
  const Pass pass{scene, scene.program("masks", "fullscreen.vert", "masks.frag")};
  // Upload E as a float texture (the G-buffer's edge pass renders it; a readback round trip
  // keeps this stage testable on its own inputs).
  const unsigned edgeTexture = uploadTexture(toFloat(edges));
  std::array<std::unique_ptr<Framebuffer>, kLevelCount> mask, stencil;
  std::array<MaskLevel, kLevelCount> out;
  // 1. mask pyramid: M_0 = E, M_ℓ = maxpool2(M_{ℓ−1}), through disabled levels too
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    const unsigned source = l == 0 ? edgeTexture : mask[static_cast<size_t>(l - 1)]->texture(0);
    mask[static_cast<size_t>(l)] = pass.run(1, lc.width, lc.height, source, 0, l == 0 ? 1 : 2);
    out[static_cast<size_t>(l)].mask = toMask(mask[static_cast<size_t>(l)]->read(0, 1));
  }
  for (int l = 0; l < kLevelCount; ++l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    MaskLevel& ml = out[static_cast<size_t>(l)];
    if (l == c.coarsestEnabled) {  // 2. the coarsest enabled level covers everything
      ml.alpha = ImageF(lc.width, lc.height, 1, 1.0f);
      ml.stencil = ImageU8(lc.width, lc.height, 1, 1);
      continue;
    }
    // 2. a_ℓ = G(σ²) ∗ M_ℓ, separable; 3. S_ℓ = [a_ℓ > 0]
    const auto horizontal =
        pass.run(2, lc.width, lc.height, mask[static_cast<size_t>(l)]->texture(0), 0, 1, {1, 0}, &lc.gaussian);
    const auto alpha = pass.run(2, lc.width, lc.height, horizontal->texture(0), 0, 1, {0, 1}, &lc.gaussian);
    ml.alpha = alpha->read(0, 1);
    stencil[static_cast<size_t>(l)] = pass.run(3, lc.width, lc.height, alpha->texture(0));
  }
  // 4. coverage closure, fine to coarse, across disabled levels
  for (int l = 0; l < kLevelCount; ++l) {
    const int next = c.nextCoarserEnabled(l);
    if (!c.levels[static_cast<size_t>(l)].enabled || next < 0) continue;
    const LevelConstants& ln = c.levels[static_cast<size_t>(next)];
    if (next == c.coarsestEnabled) continue;  // already all 1
    stencil[static_cast<size_t>(next)] = pass.run(4, ln.width, ln.height, stencil[static_cast<size_t>(l)]->texture(0),
                                                  stencil[static_cast<size_t>(next)]->texture(0), 1 << (next - l));
  }
  for (int l = 0; l < kLevelCount; ++l)
    if (c.levels[static_cast<size_t>(l)].enabled && l != c.coarsestEnabled)
      out[static_cast<size_t>(l)].stencil = toMask(stencil[static_cast<size_t>(l)]->read(0, 1));
  glDeleteTextures(1, &edgeTexture);
  return out;
}

}  // namespace mrr::gpu
