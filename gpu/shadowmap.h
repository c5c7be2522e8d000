#pragma once
// The port's shadow map (gpu/shaders/shadowmap.vert, .frag, shadowmap.glsl), mirroring
// cpu_ref/shadowmap.cpp: the scene rasterised from the light into a size² R32F target on the
// oracle's own frame (shadowMapFrame, one function for both paths), and the one-tap test at
// every pixel of the level-0 G-buffer. Both are read back into the oracle's structures.
#include "common/camera.h"
#include "common/scene.h"
#include "common/frame.h"
#include "gpu/gbuffer.h"

namespace mrr::gpu {

// A size² R32F colour target with a depth buffer: the map, kept on the GPU for later passes.
class ShadowMapTarget {
 public:
  explicit ShadowMapTarget(int size);
  ~ShadowMapTarget();
  ShadowMapTarget(const ShadowMapTarget&) = delete;
  ShadowMapTarget& operator=(const ShadowMapTarget&) = delete;
  void bind() const;
  unsigned texture() const { return texture_; }
  ImageF read() const;  // 1 channel, row 0 = texel row 0
  int size() const { return size_; }

 private:
  int size_;
  unsigned fbo_ = 0, texture_ = 0, depth_ = 0;
};

// Rasterises the distance from the light plane to the nearest surface at every texel centre
// of `frame` (its depth is not read); texels no surface covers hold ShadowMap::kNoBlocker.
void drawShadowMap(const GpuScene& scene, const ShadowMap& frame, const ShadowMapTarget& target);

// Sets shadowmap.glsl's uniforms of `program` (in use) from the map's frame and the view, and
// binds the map texture to texture unit `unit`. Shared by every pass that reads the map.
void bindShadowMap(unsigned program, const ShadowMap& map, unsigned mapTexture, int unit, const View& view,
                   float biasTexels);

// The one-tap test at every pixel of the level-0 G-buffer into `target` (1 colour target,
// level-0 size): lit in R, 1 on background. Kept on the GPU for the shadow edges.
void drawShadowTest(const GpuScene& scene, const Framebuffer& gbuffer0, const ShadowMap& map, unsigned mapTexture,
                    const View& view, float biasTexels, const Framebuffer& target);
ImageU8 readShadowTest(const Framebuffer& target);

}  // namespace mrr::gpu
