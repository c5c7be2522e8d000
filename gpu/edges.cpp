#include "gpu/edges.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "gpu/program.h"

namespace mrr::gpu {

namespace {
// One draw of edges.frag (any variant) into `target`: the level-0 G-buffer, the thresholds and,
// with a shadow test, the shadow kind's input.
void drawEdgePass(const GpuScene& scene, unsigned program, const Framebuffer& target, const Framebuffer& gbuffer0,
                  const EdgeSettings& settings, unsigned shadowLitTexture, const char* name) {
  target.bind();
  glUseProgram(program);
  bindTextures(program, {{"normalDepth", gbuffer0.texture(1)}});
  glUniform1f(uniform(program, "normalThreshold"), settings.normalThreshold);
  glUniform1f(uniform(program, "depthThreshold"), settings.depthThreshold);
  if (shadowLitTexture != 0) bindTextures(program, {{"shadowLit", shadowLitTexture}}, 1);
  scene.drawFullscreen();
  checkGl(name);
}
}  // namespace

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
  drawEdgePass(scene, program, *target, gbuffer0, settings, shadowLitTexture, "edges");
  return target;
}

Target drawEdgeSample(const GpuScene& scene, const Framebuffer& gbuffer0, const EdgeSettings& settings,
                      unsigned shadowLitTexture) {
  const bool shadowEdges = shadowLitTexture != 0;
  const unsigned program = scene.program(std::string("edgesample") + (shadowEdges ? ".shadow" : ""), "fullscreen.vert",
                                         "edges.frag",
                                         std::string("#define EDGE_SAMPLE\n") + (shadowEdges ? "#define SHADOW_EDGES\n" : ""));
  // 1–2. E at each block's diagonal pixels, a block's eight side by side in one row (3. Ê, any of
  // them, is the reader's: gpu/rule.cpp's count, or readEdgeSample)
  const int blocksX = (gbuffer0.width() + kEdgeSampleStep - 1) / kEdgeSampleStep;
  const int blocksY = (gbuffer0.height() + kEdgeSampleStep - 1) / kEdgeSampleStep;
  Target diagonals = scene.target(blocksX * kEdgeSampleStep, blocksY, 1, false, Texel::R8);
  drawEdgePass(scene, program, *diagonals, gbuffer0, settings, shadowLitTexture, "edgesample");
  return diagonals;
}

ImageU8 readEdgeSample(const Framebuffer& diagonals) {
  const ImageU8 e = diagonals.readBinary(0);
  // 3. Ê: any of a block's eight
  ImageU8 sample(e.width / kEdgeSampleStep, e.height);
  for (int y = 0; y < sample.height; ++y)
    for (int x = 0; x < sample.width; ++x) {
      uint8_t any = 0;
      for (int i = 0; i < kEdgeSampleStep; ++i) any |= e.at(x * kEdgeSampleStep + i, y);
      sample.at(x, y) = any;
    }
  return sample;
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
