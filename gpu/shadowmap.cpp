#include "gpu/shadowmap.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include "common/error.h"
#include "gpu/pass_clock.h"
#include "gpu/program.h"
#include "gpu/traffic.h"

namespace mrr::gpu {

ShadowMapTarget::ShadowMapTarget(int size) : size_(size) {
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, size, size, 0, GL_RED, GL_FLOAT, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
  glGenRenderbuffers(1, &depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, size, size);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  const GLenum buffer = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &buffer);
  require(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE, "gpu: shadow map target incomplete");
  checkGl("shadowmap target");
}

ShadowMapTarget::~ShadowMapTarget() {
  glDeleteTextures(1, &texture_);
  glDeleteRenderbuffers(1, &depth_);
  glDeleteFramebuffers(1, &fbo_);
}

void ShadowMapTarget::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, size_, size_);
}

ImageF ShadowMapTarget::read() const {
  ImageF out(size_, size_, 1);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  readImage(size_, size_, GL_RED, GL_FLOAT, out.data.data(), out.data.size() * sizeof(float));
  checkGl("shadowmap readback");
  return out;
}

namespace {
void setVec3(unsigned program, const char* name, const glm::vec3& v) {
  glUniform3f(uniform(program, name), v.x, v.y, v.z);
}

// The light frame's uniforms of shadowmap.glsl (no view, no texture).
void setFrameUniforms(unsigned program, const ShadowMap& map) {
  glUniform1i(uniform(program, "mapSize"), map.size);
  glUniform1f(uniform(program, "mapTexel"), map.texel);
  setVec3(program, "mapOrigin", map.origin);
  setVec3(program, "mapRight", map.right);
  setVec3(program, "mapUp", map.up);
  setVec3(program, "mapForward", map.forward);
}
}  // namespace

void drawShadowMap(const GpuScene& scene, const ShadowMap& frame, const ShadowMapTarget& target) {
  const unsigned program = scene.program("shadowmap", "shadowmap.vert", "shadowmap.frag");
  target.bind();
  glUseProgram(program);
  setFrameUniforms(program, frame);
  glUniform1f(uniform(program, "farDepth"), frame.farDepth);
  // 1. clear to "no blocker"; 2. the nearest surface per texel centre wins the depth test
  const float none[4] = {ShadowMap::kNoBlocker, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, none);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_DEPTH_CLAMP);  // the depth buffer only orders surfaces: never clip one away
  glDisable(GL_CULL_FACE);   // rays hit both sides of a triangle
  const TimedDraw timed;     // the meshes' draws as one
  for (const GpuScene::MeshGl& m : scene.meshes()) {
    bindCutout(program, m, 0);
    glBindVertexArray(m.vao);
    glDrawElements(GL_TRIANGLES, m.indexCount, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_DEPTH_CLAMP);
  glDisable(GL_DEPTH_TEST);
  checkGl("shadowmap");
}

void bindShadowMap(unsigned program, const ShadowMap& map, unsigned mapTexture, int unit, const View& view,
                   float biasTexels) {
  setFrameUniforms(program, map);
  glUniform1f(uniform(program, "biasTexels"), biasTexels);
  setVec3(program, "viewEye", view.eye);
  setVec3(program, "viewRight", view.right);
  setVec3(program, "viewUp", view.up);
  setVec3(program, "viewForward", view.forward);
  bindTextures(program, {{"shadowMap", mapTexture}}, unit);
}

void drawShadowTest(const GpuScene& scene, const Framebuffer& gbuffer0, const ShadowMap& map, unsigned mapTexture,
                    const View& view, float biasTexels, const Framebuffer& target) {
  const unsigned program = scene.program("shadowtest", "fullscreen.vert", "shadowmap.frag", "#define SHADOW_TEST\n");
  target.bind();
  glUseProgram(program);
  bindTextures(program, {{"positionHit", gbuffer0.texture(0)}, {"normalDepth", gbuffer0.texture(1)}});
  bindShadowMap(program, map, mapTexture, 2, view, biasTexels);
  scene.drawFullscreen();
  checkGl("shadowtest");
}

ImageU8 readShadowTest(const Framebuffer& target) { return target.readBinary(0); }

}  // namespace mrr::gpu
