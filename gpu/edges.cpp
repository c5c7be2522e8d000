#include "gpu/edges.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "gpu/program.h"

namespace mrr::gpu {

EdgeImages detectEdges(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings) {
  const unsigned program = scene.program("edges", "fullscreen.vert", "edges.frag");
  Framebuffer target(gbuffer0.width(), gbuffer0.height(), 1, false);
  target.bind();
  glUseProgram(program);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, gbuffer0.texture(0));
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, gbuffer0.texture(1));
  glUniform1i(glGetUniformLocation(program, "positionHit"), 0);
  glUniform1i(glGetUniformLocation(program, "normalDepth"), 1);
  glUniform1f(glGetUniformLocation(program, "normalThreshold"), settings.normalThreshold);
  glUniform1f(glGetUniformLocation(program, "depthThreshold"), settings.depthThreshold);
  scene.drawFullscreen();
  checkGl("edges");
  const ImageF e = target.read(0);
  EdgeImages out;
  out.normal = ImageU8(e.width, e.height);
  out.depth = ImageU8(e.width, e.height);
  out.background = ImageU8(e.width, e.height);
  out.combined = ImageU8(e.width, e.height);
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      out.normal.at(x, y) = e.at(x, y, 0) > 0.5f;
      out.depth.at(x, y) = e.at(x, y, 1) > 0.5f;
      out.background.at(x, y) = e.at(x, y, 2) > 0.5f;
      out.combined.at(x, y) = e.at(x, y, 3) > 0.5f;
    }
  return out;
}

}  // namespace mrr::gpu
