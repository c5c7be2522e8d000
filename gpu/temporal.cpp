#include "gpu/temporal.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "gpu/program.h"

namespace mrr::gpu {

Target drawTemporal(const GpuScene& scene, unsigned final, const Framebuffer& gbuffer0, unsigned stencil0,
                    unsigned alpha0, const FrameHistory& history, const View& view, const Constants& c) {
  const int channels = c.channels();
  const unsigned program = scene.program("temporal." + std::to_string(channels), "fullscreen.vert", "temporal.frag",
                                         "#define CHANNELS " + std::to_string(channels) + "\n");
  // The previous frame's images, as the oracle reads them: its result, and its depth and normal in one
  // RGBA texture (normal in rgb, depth in a).
  ImageF normalDepth(history.depth.width, history.depth.height, 4);
  for (size_t i = 0; i < history.depth.pixelCount(); ++i) {
    for (size_t k = 0; k < 3; ++k) normalDepth.data[4 * i + k] = history.normal.data[3 * i + k];
    normalDepth.data[4 * i + 3] = history.depth.data[i];
  }
  TextureSet uploaded;
  const unsigned previousResult = uploaded.add(uploadTexture(history.result));
  const unsigned previousNormalDepth = uploaded.add(uploadTexture(normalDepth));
  Target target = scene.target(c.width, c.height, {effectTexel(channels), Texel::Rgba32f}, false);
  target->bind();
  glUseProgram(program);
  bindTextures(program, {{"positionHit", gbuffer0.texture(0)},
                         {"normalDepth", gbuffer0.texture(1)},
                         {"stencil0", stencil0},
                         {"alpha0", alpha0},
                         {"blended", final},
                         {"previousResult", previousResult},
                         {"previousNormalDepth", previousNormalDepth}});
  // 1. the host's transform from this view to the previous one (common/temporal.h), as the oracle's
  const Reprojection m = makeReprojection(view, history.view);
  glUniform3f(uniform(program, "row0"), m.r[0][0], m.r[0][1], m.r[0][2]);
  glUniform3f(uniform(program, "row1"), m.r[1][0], m.r[1][1], m.r[1][2]);
  glUniform3f(uniform(program, "row2"), m.r[2][0], m.r[2][1], m.r[2][2]);
  glUniform3f(uniform(program, "offset"), m.t[0], m.t[1], m.t[2]);
  glUniform3f(uniform(program, "previousProjection"), history.view.cx, history.view.cy, history.view.focal);
  glUniform1f(uniform(program, "lambda"), c.temporal.lambda);
  glUniform1f(uniform(program, "weight0"), c.levels[0].weight);
  glUniform1f(uniform(program, "depthTolerance"), c.temporal.depthTolerance);
  glUniform1f(uniform(program, "normalCos"), c.temporal.normalCos);
  scene.drawFullscreen();
  checkGl("temporal");
  return target;
}

FrameHistory readHistory(const Framebuffer& gbuffer0, const ImageF& result, const View& view, const Constants& c) {
  FrameHistory h;
  h.view = view;
  h.result = result;
  const ImageF nd = gbuffer0.read(1);  // view normal in rgb, depth in a (padded grid)
  h.depth = ImageF::uninitialised(c.width, c.height, 1);
  h.normal = ImageF::uninitialised(c.width, c.height, 3);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      for (int k = 0; k < 3; ++k) h.normal.at(x, y, k) = nd.at(x, y, k);
      h.depth.at(x, y) = nd.at(x, y, 3);
    }
  return h;
}

}  // namespace mrr::gpu
