#include "gpu/edges.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "gpu/program.h"

namespace mrr::gpu {

Target drawEdges(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings,
                 unsigned shadowLitTexture, bool combinedOnly) {
  const bool shadowEdges = shadowLitTexture != 0;
  const std::string defines = std::string(shadowEdges ? "#define SHADOW_EDGES\n" : "") +
                              (combinedOnly ? "#define E_ONLY\n" : "");
  const unsigned program = scene.program(std::string("edges") + (shadowEdges ? ".shadow" : "") +
                                             (combinedOnly ? ".e" : ""),
                                         "fullscreen.vert", "edges.frag", defines);
  // 0/1 flags: 8 bits hold them exactly
  Target target = combinedOnly ? scene.target(gbuffer0.width(), gbuffer0.height(), 1, false, Texel::R8)
                               : scene.target(gbuffer0.width(), gbuffer0.height(), shadowEdges ? 2 : 1, false,
                                              Texel::Rgba8);
  target->bind();
  glUseProgram(program);
  bindTextures(program, {{"normalDepth", gbuffer0.texture(1)}});
  glUniform1f(uniform(program, "normalThreshold"), settings.normalThreshold);
  glUniform1f(uniform(program, "depthThreshold"), settings.depthThreshold);
  if (shadowEdges) bindTextures(program, {{"shadowLit", shadowLitTexture}}, 1);
  scene.drawFullscreen();
  checkGl("edges");
  return target;
}

EdgeImages readEdges(const Framebuffer& target) {
  const ImageF e = target.read(0, 4);
  EdgeImages out;
  if (target.targetCount() > 1) out.shadow = target.readBinary(1);
  out.normal = ImageU8(e.width, e.height);
  out.depth = ImageU8(e.width, e.height);
  out.background = ImageU8(e.width, e.height);
  out.combined = ImageU8(e.width, e.height);
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      out.normal.at(x, y) = e.at(x, y, 0) > 0.5f;
      out.depth.at(x, y) = e.at(x, y, 1) > 0.5f;
      out.background.at(x, y) = e.at(x, y, 2) > 0.5f;
      out.combined.at(x, y) = e.at(x, y, edgeChannel(false)) > 0.5f;
    }
  return out;
}

EdgeImages detectEdges(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings,
                       unsigned shadowLitTexture) {
  return readEdges(*drawEdges(scene, gbuffer0, settings, shadowLitTexture));
}

}  // namespace mrr::gpu
