#include "gpu/stencil.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <utility>

#include "gpu/program.h"

namespace mrr::gpu {

void fillStencil(const GpuScene& scene, unsigned stencilMask, const Cover& cover) {
  const unsigned fill = scene.passProgram("stencil", "stencil.frag", "", cover);
  glClearStencil(0);
  glClear(GL_STENCIL_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glUseProgram(fill);
  bindTextures(fill, {{"stencilMask", stencilMask}});
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_ALWAYS, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  GLint viewport[4];
  glGetIntegerv(GL_VIEWPORT, viewport);
  scene.draw(cover, viewport[2], viewport[3]);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glStencilFunc(GL_EQUAL, 1, 0xff);
  glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
  checkGl("stencil");
}

namespace {
// The colour target cleared to 0, the stencil buffer ready (`prepareStencil`), then the pass
// where the stencil is 1.
Target drawUnderStencil(const GpuScene& scene, Target target, unsigned program, const std::string& stage,
                        const std::function<void()>& prepareStencil, const std::function<void()>& setInputs) {
  target->bind();
  const float zero[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, zero);
  prepareStencil();
  glUseProgram(program);
  setInputs();
  scene.drawFullscreen();
  glDisable(GL_STENCIL_TEST);
  checkGl(stage);
  return target;
}
}  // namespace

Target drawStencilled(const GpuScene& scene, unsigned stencilMask, int width, int height, Texel format,
                      unsigned program, const std::string& stage, const std::function<void()>& setInputs,
                      const Cover& fill) {
  // 1. S_ℓ into the stencil buffer; 2. the pass where the stencil is 1
  return drawUnderStencil(scene, scene.target(width, height, 1, true, format), program, stage,
                          [&] { fillStencil(scene, stencilMask, fill); }, setInputs);
}

Target drawStencilledLike(const GpuScene& scene, const Framebuffer& stencilled, Texel format, unsigned program,
                          const std::string& stage, const std::function<void()>& setInputs) {
  Target target = scene.target(stencilled.width(), stencilled.height(), 1, false, format);
  target->shareDepthStencil(stencilled);
  return drawUnderStencil(scene, std::move(target), program, stage,
                          [] {
                            glEnable(GL_STENCIL_TEST);
                            glStencilFunc(GL_EQUAL, 1, 0xff);
                            glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
                          },
                          setInputs);
}

ImageF withHostStencil(const ImageU8& stencil, int channels, const std::function<Target(unsigned)>& draw) {
  TextureSet uploaded;
  const Target target = draw(uploaded.add(uploadBinary(stencil)));
  return target->read(0, channels);
}

}  // namespace mrr::gpu
