#include "gpu/blend.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <memory>

#include "gpu/program.h"

namespace mrr::gpu {

BlendResult blendLevels(const GpuScene& scene, const std::array<LevelImages, kLevelCount>& levels, const Constants& c,
                        bool keepStages) {
  const unsigned program = scene.program("blend", "fullscreen.vert", "blend.frag");
  const int channelCount = levels[static_cast<size_t>(c.coarsestEnabled)].sub->channels;
  BlendResult r;
  r.levelMap = ImageU8(c.width, c.height, 1, static_cast<uint8_t>(c.coarsestEnabled));
  std::unique_ptr<Framebuffer> previous;
  for (int l = c.coarsestEnabled; l >= 0; --l) {
    const LevelConstants& lc = c.levels[static_cast<size_t>(l)];
    if (!lc.enabled) continue;
    const LevelImages& in = levels[static_cast<size_t>(l)];
    const unsigned sub = uploadTexture(*in.sub), stencil = uploadTexture(toFloat(*in.stencil)),
                   alpha = uploadTexture(*in.alpha);
    auto target = std::make_unique<Framebuffer>(c.width, c.height, 3, false);
    target->bind();
    glUseProgram(program);
    bindTextures(program, {{"sub", sub},
                           {"stencilMask", stencil},
                           {"alphaMask", alpha},
                           {"coarser", previous ? previous->texture(2) : sub}});
    glUniform1i(glGetUniformLocation(program, "coarsest"), previous ? 0 : 1);
    glUniform1i(glGetUniformLocation(program, "scale"), lc.scale);
    glUniform1f(glGetUniformLocation(program, "weight"), lc.weight);
    scene.drawFullscreen();
    checkGl("blend");
    if (keepStages) r.upsampled[static_cast<size_t>(l)] = target->read(0, channelCount);
    const ImageF levelAlpha = target->read(1, 1);
    if (keepStages || l == c.finestEnabled) r.composite[static_cast<size_t>(l)] = target->read(2, channelCount);
    if (previous)  // the finest level with α > 0 wins the level map, as on the host
      for (size_t i = 0; i < r.levelMap.data.size(); ++i)
        if (levelAlpha.data[i] > 0.0f) r.levelMap.data[i] = static_cast<uint8_t>(l);
    if (keepStages) r.alpha[static_cast<size_t>(l)] = levelAlpha;
    glDeleteTextures(1, &sub);
    glDeleteTextures(1, &stencil);
    glDeleteTextures(1, &alpha);
    previous = std::move(target);
  }
  r.final = keepStages ? r.composite[static_cast<size_t>(c.finestEnabled)]
                       : std::move(r.composite[static_cast<size_t>(c.finestEnabled)]);
  return r;
}

}  // namespace mrr::gpu
