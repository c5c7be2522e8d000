#include "gpu/shade.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "gpu/program.h"

namespace mrr::gpu {

Target drawShade(const GpuScene& scene, const Framebuffer& gbuffer0, unsigned effect, unsigned shadowLit,
                 const View& view, const DirectionalLight& light, const Constants& c) {
  const int effectIndex = static_cast<int>(c.effect);  // 0 ssao, 1 ssm, 2 ssgi (shade.frag's EFFECT)
  const unsigned program = scene.program("shade." + std::to_string(effectIndex), "fullscreen.vert", "shade.frag",
                                         "#define EFFECT " + std::to_string(effectIndex) + "\n");
  Target target = scene.target(c.width, c.height, 1, false);
  target->bind();
  glUseProgram(program);
  bindTextures(program, {{"positionHit", gbuffer0.texture(0)},
                         {"normalDepth", gbuffer0.texture(1)},
                         {"albedo", gbuffer0.texture(2)},
                         {"effect", effect}});
  if (c.effect == Effect::Ssgi) bindTextures(program, {{"shadowLit", shadowLit}}, 4);
  // the host's unit vector, as cpu_ref/shade.cpp computes it
  const glm::vec3 toLight = -glm::normalize(view.directionToView(light.direction));
  glUniform3f(uniform(program, "toLight"), toLight.x, toLight.y, toLight.z);
  glUniform3f(uniform(program, "lightColor"), light.color.x, light.color.y, light.color.z);
  scene.drawFullscreen();
  checkGl("shade");
  return target;
}

}  // namespace mrr::gpu
