#pragma once
// The port's stage 1 (gpu/shaders/gbuffer.vert, .frag): the scene uploaded once, the full-res
// G-buffer rasterised, each coarser level's subsampled from it, and either read back into the
// oracle's GBuffer structure.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/camera.h"
#include "common/params.h"
#include "common/scene.h"
#include "common/frame.h"

namespace mrr::gpu {

// The texel format of a colour target. Each stage stores what it needs and no more, so the
// full-screen passes move fewer bytes: 0/1 images (edges, M_ℓ, S_ℓ, the level map) in 8 bits,
// which hold 0 and 1 exactly; one-channel values (a_ℓ, AO, V) in R32F; RGB in RGBA32F (RGB32F
// is not colour-renderable in GL 3.3).
// RGBA32UI holds counts (gpu/counts.h: a few per block, summed on the GPU).
enum class Texel { Rgba32f, R32f, R8, Rgba8, Rgba32ui };

// The float format that holds `channels` effect channels (1: R32F, 3: RGBA32F).
Texel effectTexel(int channels);

class GpuScene;
class ShadowMapTarget;

// A colour target set for a full-screen or geometry pass (+ depth and stencil).
class Framebuffer {
 public:
  Framebuffer(int width, int height, int colorTargets, bool withDepth, Texel format = Texel::Rgba32f);
  Framebuffer(int width, int height, const std::vector<Texel>& formats, bool withDepth);
  ~Framebuffer();
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;
  void bind() const;
  unsigned texture(int i) const { return textures_[static_cast<size_t>(i)]; }
  // Copies target `i` of `source` (same size and format) into this one's only target, texel for
  // texel (glBlitFramebuffer, nearest), and leaves this one bound.
  void copyFrom(const Framebuffer& source, int i) const;
  ImageF read(int i) const;  // RGBA float, row 0 = image row 0
  ImageF read(int i, int channels) const;  // the first `channels` of target i
  ImageU8 readBinary(int i) const;  // channel r of target i as 0/1 (> ½), row 0 = image row 0
  ImageF readChannel(int i, int channel) const;  // one channel (0–2) of a float target i: a quarter of read(i)
  std::vector<uint32_t> readUint(int i) const;  // an RGBA32UI target's texels, 4 a texel, row-major
  ImageU8 readBytes(int i) const;   // an R8 target's bytes as stored (a level index: ℓ/255 → ℓ)
  int width() const { return width_; }
  int height() const { return height_; }
  int targetCount() const { return static_cast<int>(textures_.size()); }
  // Attaches `other`'s depth and stencil buffer (same size; `other` must outlive this), so a
  // pass can reuse the stencil an earlier pass filled.
  void shareDepthStencil(const Framebuffer& other);
  // What a pool matches on: size, formats, own depth-stencil buffer.
  bool matches(int width, int height, const std::vector<Texel>& formats, bool withDepth) const;
  void detachSharedDepthStencil();  // undoes shareDepthStencil (before the pool hands it out again)

 private:
  int width_, height_;
  unsigned fbo_ = 0, depth_ = 0;
  bool sharedDepth_ = false;
  std::vector<unsigned> textures_;
  std::vector<Texel> formats_;
};

// Hands a target back to the pool of the GpuScene that made it (GpuScene::target).
struct TargetRelease {
  const GpuScene* pool = nullptr;
  void operator()(Framebuffer* target) const;
};
using Target = std::unique_ptr<Framebuffer, TargetRelease>;

// An image kept on the GPU: a pooled target and which colour attachment of it holds the image.
struct GpuImage {
  Target target;
  int attachment = 0;
  unsigned texture() const { return target ? target->texture(attachment) : 0; }
};

// A block map (gpu/blocks.h): an R8 attachment of a target, one texel per block, 1 where the
// block may hold a pass's work.
struct BlockMap {
  const Framebuffer* target = nullptr;
  int attachment = 0;
  BlockMap() = default;
  BlockMap(const Framebuffer& t, int a = 0) : target(&t), attachment(a) {}  // NOLINT: a target's map
  explicit operator bool() const { return target != nullptr; }
  unsigned texture() const { return target->texture(attachment); }
  int width() const { return target->width(); }
  int height() const { return target->height(); }
};

// Where an image-space pass is drawn: every pixel of its target, host rectangles, or the runs of
// a block map on the GPU (blocks.geom). A pass drawn over part of its target clears the rest to
// what it gives there. Block covers keep the frame resident: the host never sees where the work is.
struct Cover {
  const std::vector<glm::ivec4>* rects = nullptr;  // pixel rectangles (x0, y0, x1, y1) of the target
  unsigned blocks = 0;    // a block map (R8, 1 = set): its runs of `value`
  int blockWidth = 0, blockHeight = 0;  // the map's grid
  int blockSize = 0;      // target pixels per block side
  int value = 1;          // 1: the set blocks; 0: the clear ones
  static Cover whole() { return {}; }
  static Cover over(const std::vector<glm::ivec4>* r) { return {r, 0, 0, 0, 0, 1}; }
  // `map`'s runs of `value`, blockSize pixels a block.
  static Cover blocksOf(const BlockMap& map, int blockSize, int value = 1);
  bool isWhole() const { return !rects && !blocks; }
  bool byBlocks() const { return blocks != 0; }
};

// A float image as a texture (1–4 channels, nearest filtering); the caller deletes it.
unsigned uploadTexture(const ImageF& image);

// A 0/1 image as an R8 texture (sampled as 0.0 and 1.0); the caller deletes it.
unsigned uploadBinary(const ImageU8& image);

// Textures a stage uploaded from host images, deleted with it.
class TextureSet {
 public:
  TextureSet() = default;
  ~TextureSet();
  TextureSet(const TextureSet&) = delete;
  TextureSet& operator=(const TextureSet&) = delete;
  unsigned add(unsigned texture) {
    textures_.push_back(texture);
    return texture;
  }

 private:
  std::vector<unsigned> textures_;
};

// A host sample kernel (kernels.h) as an N×1 RGB32F texture; the caller deletes it.
unsigned uploadKernel(const std::vector<glm::vec3>& kernel);

class GpuScene {
 public:
  explicit GpuScene(const Scene& scene);
  ~GpuScene();
  GpuScene(const GpuScene&) = delete;
  GpuScene& operator=(const GpuScene&) = delete;

  struct MeshGl {
    unsigned vao = 0, positions = 0, normals = 0, texcoords = 0, indices = 0;
    int indexCount = 0;
    glm::vec3 color{0.0f};
    unsigned cutout = 0;         // the R8 texture of its alpha cutout, or 0: opaque
    glm::ivec2 cutoutWrap{0};    // wrapS, wrapT as cutout.glsl numbers them
    unsigned texture = 0;        // the RGBA8 texture of its base colour, or 0: the factor alone
    glm::ivec2 textureWrap{0};   // wrapS, wrapT as albedo.glsl numbers them
  };
  const std::vector<MeshGl>& meshes() const { return meshes_; }
  const Bounds& bounds() const { return bounds_; }
  unsigned srgbToLinear() const { return srgbToLinear_; }  // the 256x1 R32F table albedo.glsl reads

  // The program of a stage, compiled on first use in this context and kept (keyed by stage,
  // so each variant of a file, with its own `defines`, needs its own stage name).
  unsigned program(const std::string& stage, const std::string& vertex, const std::string& fragment,
                   const std::string& defines = "") const;
  // An image-space pass's program for `cover`: `fragment` with fullscreen.vert (every pixel, host
  // rectangles) or with blocks.vert and blocks.geom (a block map's runs), keyed `stage` (+ ".blocks").
  unsigned passProgram(const std::string& stage, const std::string& fragment, const std::string& defines,
                       const Cover& cover) const;
  // Draws the program in use (passProgram's for `cover`) over `cover` of a width×height target.
  void draw(const Cover& cover, int width, int height) const;
  // A render target from the scene's pool: a free one of this size and these formats (from an
  // earlier pass or frame) or a new one, back in the pool when the Target is dropped. Its
  // contents are undefined: every pass clears it or writes every pixel. New textures cost the
  // first write page faults (on llvmpipe a 1080p RGBA32F target's first pass takes ~3× as long
  // as a reused one's), so a frame's targets are made once, not every frame.
  Target target(int width, int height, const std::vector<Texel>& formats, bool withDepth) const;
  Target target(int width, int height, int colorTargets, bool withDepth, Texel format = Texel::Rgba32f) const;
  void release(Framebuffer* target) const;
  // The shadow map's target of this size (SSM, and SSGI's direct light), kept from frame to frame
  // for the same reason; a new size replaces it.
  ShadowMapTarget& shadowMapTarget(int size) const;

  // Draws the full-screen triangle (image-space passes; vertex shader fullscreen.vert).
  void drawFullscreen() const;
  // Draws pixel rectangles (x0, y0, x1, y1: the pixels [x0, x1) × [y0, y1)) of a width×height
  // target, two triangles each, with the program in use (its vertex shader: fullscreen.vert).
  void drawRects(const std::vector<glm::ivec4>& rects, int width, int height) const;

 private:
  std::vector<MeshGl> meshes_;
  std::vector<unsigned> cutouts_;  // one R8 texture per Scene::cutouts entry
  std::vector<unsigned> textures_;  // one RGBA8 texture per Scene::textures entry
  unsigned srgbToLinear_ = 0;
  Bounds bounds_;
  unsigned emptyVao_ = 0, rectVao_ = 0, rectBuffer_ = 0;
  mutable std::map<std::string, unsigned> programs_;
  mutable std::vector<std::unique_ptr<Framebuffer>> free_;  // the pool, most recently freed last
  mutable std::unique_ptr<ShadowMapTarget> shadowMapTarget_;
};

// Rasterises the full-res (level 0) G-buffer into `target` (the padded full-res size, + depth):
// position and hit, normal and depth, and albedo when the target has a third colour target.
void drawGBuffer(const GpuScene& scene, const View& view, const Framebuffer& target);

// Level ℓ's G-buffer from level 0's three targets `full` (SPEC §1; gbuffer.frag SUBSAMPLE):
// pixel (x, y) of `target` (level-sized) is full-res pixel (x·s + ⌊s/2⌋, y·s + ⌊s/2⌋), copied.
void subsampleGBuffer(const GpuScene& scene, const Framebuffer& full, const LevelConstants& level,
                      const Framebuffer& target);

// Sets cutout.glsl's uniforms for one mesh of a geometry pass (its texture on unit `unit`).
void bindCutout(unsigned program, const GpuScene::MeshGl& mesh, int unit);

// Sets albedo.glsl's uniforms for one mesh of the G-buffer pass (its base-colour texture on
// unit `unit`; the sRGB table is bound once by drawGBuffer).
void bindColorTexture(unsigned program, const GpuScene::MeshGl& mesh, int unit);

// Reads drawn G-buffer targets back into the oracle's structure.
GBuffer readGBuffer(const Framebuffer& target);

// Level `level`'s G-buffer as the pipeline makes it, into `target` (level-sized, three targets):
// level 0 rasterised, a coarser level subsampled from a level 0 drawn for it (the pipeline
// draws level 0 once and subsamples it for every coarser level).
void drawLevelGBuffer(const GpuScene& scene, const View& view, const LevelConstants& level, const Framebuffer& target);

// drawLevelGBuffer and read back in one call.
GBuffer renderGBuffer(const GpuScene& scene, const View& view, const LevelConstants& level);

}  // namespace mrr::gpu
