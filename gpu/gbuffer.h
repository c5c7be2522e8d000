#pragma once
// The port's stage 1 (gpu/shaders/gbuffer.vert, .frag): the scene uploaded once, each level's
// G-buffer rasterised at its own size and read back into the oracle's GBuffer structure.
#include <map>
#include <string>
#include <vector>

#include "common/camera.h"
#include "common/params.h"
#include "common/scene.h"
#include "cpu_ref/gbuffer.h"

namespace mrr::gpu {

// A colour target set for a full-screen or geometry pass: float RGBA textures (+ depth).
class Framebuffer {
 public:
  Framebuffer(int width, int height, int colorTargets, bool withDepth);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;
  void bind() const;
  unsigned texture(int i) const { return textures_[static_cast<size_t>(i)]; }
  ImageF read(int i) const;  // RGBA float, row 0 = image row 0
  ImageF read(int i, int channels) const;  // the first `channels` of target i
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_, height_;
  unsigned fbo_ = 0, depth_ = 0;
  std::vector<unsigned> textures_;
};

// A float image as a texture (1–4 channels, nearest filtering); the caller deletes it.
unsigned uploadTexture(const ImageF& image);

// A host sample kernel (kernels.h) as an N×1 RGB32F texture; the caller deletes it.
unsigned uploadKernel(const std::vector<glm::vec3>& kernel);

class GpuScene {
 public:
  explicit GpuScene(const Scene& scene);
  ~GpuScene();
  GpuScene(const GpuScene&) = delete;
  GpuScene& operator=(const GpuScene&) = delete;

  struct MeshGl {
    unsigned vao = 0, positions = 0, normals = 0, indices = 0;
    int indexCount = 0;
    glm::vec3 color{0.0f};
  };
  const std::vector<MeshGl>& meshes() const { return meshes_; }
  const Bounds& bounds() const { return bounds_; }

  // The program of a stage, compiled on first use in this context and kept (keyed by stage,
  // so each variant of a file, with its own `defines`, needs its own stage name).
  unsigned program(const std::string& stage, const std::string& vertex, const std::string& fragment,
                   const std::string& defines = "") const;
  // Draws the full-screen triangle (image-space passes).
  void drawFullscreen() const;

 private:
  std::vector<MeshGl> meshes_;
  Bounds bounds_;
  unsigned emptyVao_ = 0;
  mutable std::map<std::string, unsigned> programs_;
};

// Renders level `level`'s G-buffer into `target` (3 colour targets + depth, level-sized).
void drawGBuffer(const GpuScene& scene, const View& view, const LevelConstants& level, const Framebuffer& target);

// Reads drawn G-buffer targets back into the oracle's structure.
GBuffer readGBuffer(const Framebuffer& target);

// Draw and read back in one call.
GBuffer renderGBuffer(const GpuScene& scene, const View& view, const LevelConstants& level);

}  // namespace mrr::gpu
