#include "gpu/gbuffer.h"

#include "gpu/shadowmap.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>

#include "common/error.h"
#include "common/shader_constants.h"
#include "gpu/pass_clock.h"
#include "gpu/program.h"
#include "gpu/traffic.h"

namespace mrr::gpu {

namespace {
struct TexelLayout {
  GLint internal;
  GLenum format, type;
};
TexelLayout layoutOf(Texel t) {
  switch (t) {
    case Texel::R32f: return {GL_R32F, GL_RED, GL_FLOAT};
    case Texel::R8: return {GL_R8, GL_RED, GL_UNSIGNED_BYTE};
    case Texel::Rgba8: return {GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE};
    case Texel::Rgba32ui: return {GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT};
    case Texel::Rgba32f: break;
  }
  return {GL_RGBA32F, GL_RGBA, GL_FLOAT};
}
int channelsOf(Texel t) { return t == Texel::R32f || t == Texel::R8 ? 1 : 4; }
}  // namespace

Texel effectTexel(int channels) { return channels == 1 ? Texel::R32f : Texel::Rgba32f; }

Framebuffer::Framebuffer(int width, int height, int colorTargets, bool withDepth, Texel format)
    : Framebuffer(width, height, std::vector<Texel>(static_cast<size_t>(colorTargets), format), withDepth) {}

Framebuffer::Framebuffer(int width, int height, const std::vector<Texel>& formats, bool withDepth)
    : width_(width), height_(height), formats_(formats) {
  const int colorTargets = static_cast<int>(formats.size());
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  textures_.resize(formats.size());
  glGenTextures(colorTargets, textures_.data());
  std::vector<GLenum> buffers;
  for (int i = 0; i < colorTargets; ++i) {
    const TexelLayout t = layoutOf(formats[static_cast<size_t>(i)]);
    glBindTexture(GL_TEXTURE_2D, textures_[static_cast<size_t>(i)]);
    glTexImage2D(GL_TEXTURE_2D, 0, t.internal, width, height, 0, t.format, t.type, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), GL_TEXTURE_2D,
                           textures_[static_cast<size_t>(i)], 0);
    buffers.push_back(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  }
  if (withDepth) {
    glGenRenderbuffers(1, &depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);  // depth, and the stencil S_ℓ
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_);
  }
  glDrawBuffers(colorTargets, buffers.data());
  require(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE, "gpu: framebuffer incomplete");
  checkGl("framebuffer");
}

bool Framebuffer::matches(int width, int height, const std::vector<Texel>& formats, bool withDepth) const {
  return width_ == width && height_ == height && formats_ == formats && (depth_ != 0) == withDepth;
}

void Framebuffer::detachSharedDepthStencil() {
  if (!sharedDepth_) return;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, 0);
  sharedDepth_ = false;
}

void Framebuffer::shareDepthStencil(const Framebuffer& other) {
  require(other.depth_ != 0 && other.width_ == width_ && other.height_ == height_,
          "gpu: shared depth-stencil buffer of another size");
  require(depth_ == 0, "gpu: framebuffer already has a depth-stencil buffer");
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, other.depth_);
  sharedDepth_ = true;
  require(glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE, "gpu: framebuffer incomplete");
}

Framebuffer::~Framebuffer() {
  glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  if (depth_) glDeleteRenderbuffers(1, &depth_);
  glDeleteFramebuffers(1, &fbo_);
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width_, height_);
}

void Framebuffer::copyFrom(const Framebuffer& source, int i) const {
  require(source.width_ == width_ && source.height_ == height_ && textures_.size() == 1 &&
              source.formats_[static_cast<size_t>(i)] == formats_[0],
          "Framebuffer::copyFrom: another size or format");
  glBindFramebuffer(GL_READ_FRAMEBUFFER, source.fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_);
  glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  bind();
  checkGl("copy target");
}

unsigned uploadTexture(const ImageF& image) {
  static const GLenum formats[5] = {0, GL_R32F, GL_RG32F, GL_RGB32F, GL_RGBA32F};
  static const GLenum layouts[5] = {0, GL_RED, GL_RG, GL_RGB, GL_RGBA};
  unsigned texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(formats[image.channels]), image.width, image.height, 0,
               layouts[image.channels], GL_FLOAT, image.data.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // no mipmaps: else incomplete, reads 0
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  checkGl("upload texture");
  return texture;
}

unsigned uploadKernel(const std::vector<glm::vec3>& kernel) {
  ImageF image(static_cast<int>(kernel.size()), 1, 3);
  for (size_t i = 0; i < kernel.size(); ++i)
    for (int c = 0; c < 3; ++c) image.data[3 * i + static_cast<size_t>(c)] = kernel[i][c];
  return uploadTexture(image);
}

ImageF Framebuffer::read(int i) const { return read(i, 4); }

ImageF Framebuffer::read(int i, int channels) const {
  // Read in the target's own layout (a copy, no conversion in the driver), then keep
  // the first `channels`.
  const Texel t = formats_[static_cast<size_t>(i)];
  const TexelLayout layout = layoutOf(t);
  const int stored = channelsOf(t);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  ImageF out(width_, height_, channels);
  const size_t pixels = out.pixelCount();
  if (layout.type == GL_FLOAT && stored == channels) {
    readImage(width_, height_, layout.format, GL_FLOAT, out.data.data(), out.data.size() * sizeof(float));
  } else if (layout.type == GL_FLOAT) {
    std::vector<float> texels(pixels * static_cast<size_t>(stored));
    readImage(width_, height_, layout.format, GL_FLOAT, texels.data(), texels.size() * sizeof(float));
    for (size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < channels; ++c)
        out.data[p * static_cast<size_t>(channels) + static_cast<size_t>(c)] =
            c < stored ? texels[p * static_cast<size_t>(stored) + static_cast<size_t>(c)] : (c == 3 ? 1.0f : 0.0f);
  } else {
    std::vector<uint8_t> texels(pixels * static_cast<size_t>(stored));
    readImage(width_, height_, layout.format, GL_UNSIGNED_BYTE, texels.data(), texels.size());
    for (size_t p = 0; p < pixels; ++p)
      for (int c = 0; c < channels; ++c)
        out.data[p * static_cast<size_t>(channels) + static_cast<size_t>(c)] =
            c < stored ? static_cast<float>(texels[p * static_cast<size_t>(stored) + static_cast<size_t>(c)]) / 255.0f
                       : (c == 3 ? 1.0f : 0.0f);
  }
  checkGl("readback");
  return out;
}

ImageF Framebuffer::readChannel(int i, int channel) const {
  require(layoutOf(formats_[static_cast<size_t>(i)]).type == GL_FLOAT && channel >= 0 && channel < 3,
          "gpu: readChannel needs a float target and channel 0, 1 or 2");
  const GLenum formats[3] = {GL_RED, GL_GREEN, GL_BLUE};
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  ImageF out = ImageF::uninitialised(width_, height_, 1);
  readImage(width_, height_, formats[channel], GL_FLOAT, out.data.data(), out.data.size() * sizeof(float));
  checkGl("readback");
  return out;
}

ImageU8 Framebuffer::readBytes(int i) const {
  require(formats_[static_cast<size_t>(i)] == Texel::R8, "gpu: readBytes needs an R8 target");
  ImageU8 out(width_, height_);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  readImage(width_, height_, GL_RED, GL_UNSIGNED_BYTE, out.data.data(), out.data.size());
  checkGl("readback");
  return out;
}

std::vector<uint32_t> Framebuffer::readUint(int i) const {
  require(formats_[static_cast<size_t>(i)] == Texel::Rgba32ui, "gpu: readUint needs an RGBA32UI target");
  std::vector<uint32_t> out(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i));
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  readImage(width_, height_, GL_RGBA_INTEGER, GL_UNSIGNED_INT, out.data(), out.size() * sizeof(uint32_t));
  checkGl("readback");
  return out;
}

ImageU8 Framebuffer::readBinary(int i) const {
  ImageU8 out(width_, height_);
  if (formats_[static_cast<size_t>(i)] == Texel::R8) {  // one byte a texel: read as it is stored
    out = readBytes(i);
    for (uint8_t& v : out.data) v = v > 127 ? 1 : 0;
    return out;
  }
  const ImageF values = read(i, 1);
  for (size_t p = 0; p < out.data.size(); ++p) out.data[p] = values.data[p] > 0.5f ? 1 : 0;
  return out;
}

unsigned uploadBinary(const ImageU8& image) {
  std::vector<uint8_t> bytes(image.data.size());
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = image.data[i] ? 255 : 0;
  unsigned texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, image.width, image.height, 0, GL_RED, GL_UNSIGNED_BYTE, bytes.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  checkGl("upload texture");
  return texture;
}

TextureSet::~TextureSet() {
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
}

namespace {
// A vec2 or vec3 vertex attribute at `location` of the bound vertex array.
template <class Vec>
unsigned uploadAttribute(unsigned location, const std::vector<Vec>& values) {
  unsigned buffer = 0;
  glGenBuffers(1, &buffer);
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(values.size() * sizeof(Vec)), values.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(location, Vec::length(), GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(location);
  return buffer;
}

// An alpha cutout's opaque bits as an R8 texture (1.0 opaque), read with texelFetch.
// A texture of the scene's within this GL's size limit; MrrError naming `what` otherwise.
void requireTextureFits(int width, int height, const std::string& what) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  require(width <= maxSize && height <= maxSize,
          "gpu: " + what + " of " + std::to_string(width) + "x" + std::to_string(height) +
              " texels is over this GL's texture limit of " + std::to_string(maxSize));
}

unsigned uploadCutout(const Cutout& cutout) {
  requireTextureFits(cutout.width, cutout.height, "an alpha cutout");
  ImageU8 bits(cutout.width, cutout.height, 1, 0);
  bits.data.assign(cutout.opaque.begin(), cutout.opaque.end());
  return uploadBinary(bits);
}

// A base-colour texture's bytes as an RGBA8 texture, read with texelFetch (byte/255, no sRGB
// decoding by the driver: albedo.glsl decodes through the host's table).
unsigned uploadColorTexture(const ColorTexture& texture) {
  requireTextureFits(texture.width, texture.height, "a base-colour texture");
  unsigned id = 0;
  glGenTextures(1, &id);
  glBindTexture(GL_TEXTURE_2D, id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, texture.width, texture.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
               texture.rgba.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  checkGl("upload base-colour texture");
  return id;
}

int wrapNumber(Wrap wrap) { return wrap == Wrap::Clamp ? 1 : wrap == Wrap::Mirror ? 2 : 0; }
}  // namespace

GpuScene::GpuScene(const Scene& scene) : bounds_(scene.bounds()) {
  for (const Cutout& cutout : scene.cutouts) cutouts_.push_back(uploadCutout(cutout));
  for (const ColorTexture& texture : scene.textures) textures_.push_back(uploadColorTexture(texture));
  {
    ImageF table(256, 1, 1);
    const float* linear = srgbToLinearTable();
    for (int i = 0; i < 256; ++i) table.data[static_cast<size_t>(i)] = linear[i];
    srgbToLinear_ = uploadTexture(table);
  }
  for (const Mesh& mesh : scene.meshes) {
    MeshGl m;
    m.color = mesh.baseColor;
    if (mesh.texture >= 0) {
      const ColorTexture& texture = scene.textures[static_cast<size_t>(mesh.texture)];
      m.texture = textures_[static_cast<size_t>(mesh.texture)];
      m.textureWrap = {wrapNumber(texture.wrapS), wrapNumber(texture.wrapT)};
    }
    if (mesh.cutout >= 0) {
      const Cutout& cutout = scene.cutouts[static_cast<size_t>(mesh.cutout)];
      m.cutout = cutouts_[static_cast<size_t>(mesh.cutout)];
      m.cutoutWrap = {wrapNumber(cutout.wrapS), wrapNumber(cutout.wrapT)};
    }
    m.indexCount = static_cast<int>(mesh.indices.size());
    glGenVertexArrays(1, &m.vao);
    glBindVertexArray(m.vao);
    m.positions = uploadAttribute(0, mesh.positions);
    m.normals = uploadAttribute(1, mesh.normals);
    if (!mesh.texcoords.empty()) m.texcoords = uploadAttribute(2, mesh.texcoords);
    glGenBuffers(1, &m.indices);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m.indices);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)),
                 mesh.indices.data(), GL_STATIC_DRAW);
    meshes_.push_back(m);
  }
  glBindVertexArray(0);
  glGenVertexArrays(1, &emptyVao_);
  glGenVertexArrays(1, &rectVao_);
  glBindVertexArray(rectVao_);
  glGenBuffers(1, &rectBuffer_);
  glBindBuffer(GL_ARRAY_BUFFER, rectBuffer_);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glBindVertexArray(0);
  checkGl("upload");
}

unsigned GpuScene::program(const std::string& stage, const std::string& vertex, const std::string& fragment,
                           const std::string& defines) const {
  auto it = programs_.find(stage);
  if (it == programs_.end()) it = programs_.emplace(stage, compileProgram(stage, vertex, fragment, defines)).first;
  return it->second;
}

void TargetRelease::operator()(Framebuffer* target) const {
  if (pool)
    pool->release(target);
  else
    delete target;
}

Target GpuScene::target(int width, int height, const std::vector<Texel>& formats, bool withDepth) const {
  for (size_t i = free_.size(); i-- > 0;)
    if (free_[i]->matches(width, height, formats, withDepth)) {
      Framebuffer* reused = free_[i].release();
      free_.erase(free_.begin() + static_cast<std::ptrdiff_t>(i));
      return Target(reused, TargetRelease{this});
    }
  return Target(new Framebuffer(width, height, formats, withDepth), TargetRelease{this});
}

Target GpuScene::target(int width, int height, int colorTargets, bool withDepth, Texel format) const {
  return target(width, height, std::vector<Texel>(static_cast<size_t>(colorTargets), format), withDepth);
}

ShadowMapTarget& GpuScene::shadowMapTarget(int size) const {
  if (!shadowMapTarget_ || shadowMapTarget_->size() != size) {
    shadowMapTarget_.reset();
    shadowMapTarget_ = std::make_unique<ShadowMapTarget>(size);
  }
  return *shadowMapTarget_;
}

void GpuScene::release(Framebuffer* target) const {
  constexpr size_t kMaxFree = 64;  // a frame's working set, a few times over
  target->detachSharedDepthStencil();
  free_.emplace_back(target);
  if (free_.size() > kMaxFree) free_.erase(free_.begin());  // the least recently freed
}

void GpuScene::drawRects(const std::vector<glm::ivec4>& rects, int width, int height) const {
  GLint current = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &current);
  const unsigned program = static_cast<unsigned>(current);
  if (rects.empty()) return;
  std::vector<glm::vec2> corners;
  corners.reserve(rects.size() * 6);
  for (const glm::ivec4& r : rects) {
    const glm::vec2 a(static_cast<float>(r.x), static_cast<float>(r.y)), b(static_cast<float>(r.z), static_cast<float>(r.w));
    corners.insert(corners.end(), {a, {b.x, a.y}, b, a, b, {a.x, b.y}});
  }
  glUniform1i(uniform(program, "useRects"), 1);
  glUniform2f(uniform(program, "targetSize"), static_cast<float>(width), static_cast<float>(height));
  glBindVertexArray(rectVao_);
  glBindBuffer(GL_ARRAY_BUFFER, rectBuffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(corners.size() * sizeof(glm::vec2)), corners.data(),
               GL_STREAM_DRAW);
  const TimedDraw timed;
  glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(corners.size()));
  glBindVertexArray(0);
}

Cover Cover::blocksOf(const BlockMap& map, int blockSize, int value) {
  Cover c;
  c.blocks = map.texture();
  c.blockWidth = map.width();
  c.blockHeight = map.height();
  c.blockSize = blockSize;
  c.value = value;
  return c;
}

unsigned GpuScene::passProgram(const std::string& stage, const std::string& fragment, const std::string& defines,
                               const Cover& cover) const {
  return cover.byBlocks() ? program(stage + ".blocks", "blocks.vert", fragment, defines)
                          : program(stage, "fullscreen.vert", fragment, defines);
}

void GpuScene::draw(const Cover& cover, int width, int height) const {
  if (cover.rects) return drawRects(*cover.rects, width, height);
  if (!cover.blocks) return drawFullscreen();
  // blocks.geom: a point per row of the map and segment of kBlockSegment blocks along it, which
  // reads the map packed, a segment a texel of four words (blocks.frag STEP 4), drawn here first
  static_assert(2 * kBlockSegment == 256 && kBlockSegment == 4 * 32, "blocks.geom's max_vertices and its four words a texel");
  constexpr int kBlockUnit = 15;  // the last unit GL 3.3 guarantees: the passes' own textures sit below
  GLint current = 0, framebuffer = 0, viewport[4] = {};
  glGetIntegerv(GL_CURRENT_PROGRAM, &current);
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
  glGetIntegerv(GL_VIEWPORT, viewport);
  const unsigned program = static_cast<unsigned>(current);
  const int segments = (cover.blockWidth + kBlockSegment - 1) / kBlockSegment;
  glActiveTexture(GL_TEXTURE0 + kBlockUnit);  // a new target's texture binds there, not over a pass's own
  const Target packed = target(segments, cover.blockHeight, {Texel::Rgba32ui}, false);
  packed->bind();
  const unsigned pack = this->program("blocks.pack", "fullscreen.vert", "blocks.frag", "#define STEP 4\n#define UNITE 0\n");
  glUseProgram(pack);
  glBindTexture(GL_TEXTURE_2D, cover.blocks);
  glUniform1i(uniform(pack, "source"), kBlockUnit);
  // the caller's pass may have set tests and masks for its own target (the stencil fill writes no
  // colour): the pack is drawn without them
  GLboolean colorMask[4] = {};
  glGetBooleanv(GL_COLOR_WRITEMASK, colorMask);
  const GLenum tests[] = {GL_STENCIL_TEST, GL_DEPTH_TEST, GL_SCISSOR_TEST, GL_BLEND};
  bool enabled[4] = {};
  for (size_t i = 0; i < 4; ++i) {
    enabled[i] = glIsEnabled(tests[i]) == GL_TRUE;
    glDisable(tests[i]);
  }
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  drawFullscreen();
  glColorMask(colorMask[0], colorMask[1], colorMask[2], colorMask[3]);
  for (size_t i = 0; i < 4; ++i)
    if (enabled[i]) glEnable(tests[i]);
  glBindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(framebuffer));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  glUseProgram(program);
  glBindTexture(GL_TEXTURE_2D, packed->texture(0));
  glUniform1i(uniform(program, "blockBits"), kBlockUnit);
  glUniform2i(uniform(program, "blockGrid"), cover.blockWidth, cover.blockHeight);
  glUniform1i(uniform(program, "blockValue"), cover.value);
  glUniform1i(uniform(program, "blockSize"), cover.blockSize);
  glUniform1i(uniform(program, "segments"), segments);
  glUniform2f(uniform(program, "targetSize"), static_cast<float>(width), static_cast<float>(height));
  glBindVertexArray(emptyVao_);
  const TimedDraw timed;
  glDrawArrays(GL_POINTS, 0, segments * cover.blockHeight);
  glBindVertexArray(0);
}

void GpuScene::drawFullscreen() const {
  GLint program = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  glUniform1i(uniform(static_cast<unsigned>(program), "useRects"), 0);
  glBindVertexArray(emptyVao_);
  const TimedDraw timed;
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

GpuScene::~GpuScene() {
  free_.clear();
  shadowMapTarget_.reset();
  for (const auto& [stage, program] : programs_) glDeleteProgram(program);
  if (!cutouts_.empty()) glDeleteTextures(static_cast<GLsizei>(cutouts_.size()), cutouts_.data());
  if (!textures_.empty()) glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
  glDeleteTextures(1, &srgbToLinear_);
  glDeleteVertexArrays(1, &emptyVao_);
  glDeleteVertexArrays(1, &rectVao_);
  glDeleteBuffers(1, &rectBuffer_);
  for (MeshGl& m : meshes_) {
    glDeleteBuffers(1, &m.positions);
    glDeleteBuffers(1, &m.normals);
    if (m.texcoords) glDeleteBuffers(1, &m.texcoords);
    glDeleteBuffers(1, &m.indices);
    glDeleteVertexArrays(1, &m.vao);
  }
}

void drawGBuffer(const GpuScene& scene, const View& view, const Framebuffer& target) {
  const unsigned program = scene.program("gbuffer", "gbuffer.vert", "gbuffer.frag");
  // World → view, as View::toView: rows are right, up, −forward.
  const glm::vec3 r = view.right, u = view.up, f = view.forward, e = view.eye;
  const float worldToView[16] = {r.x, u.x, -f.x, 0, r.y, u.y, -f.y, 0, r.z, u.z, -f.z, 0,
                                 -glm::dot(r, e), -glm::dot(u, e), glm::dot(f, e), 1};
  const float wp = static_cast<float>(view.paddedWidth), hp = static_cast<float>(view.paddedHeight);
  // Near and far from the bounds: the G-buffer's depth comes from the interpolated position,
  // so the depth buffer only has to order surfaces.
  const Bounds& b = scene.bounds();
  float nearest = 3.0e38f, farthest = 0.0f;
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 c((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
    const float z = glm::dot(c - e, f);
    nearest = std::min(nearest, z);
    farthest = std::max(farthest, z);
  }
  const float farZ = std::max(farthest * 1.01f, 1e-3f);
  const float nearZ = std::max(nearest * 0.99f, farZ * 1e-5f);
  target.bind();
  glUseProgram(program);
  glUniformMatrix4fv(uniform(program, "worldToView"), 1, GL_FALSE, worldToView);
  glUniform4f(uniform(program, "projection"), 2.0f * view.focal / wp, 2.0f * view.cx / wp - 1.0f,
              -2.0f * view.focal / hp, 2.0f * view.cy / hp - 1.0f);
  glUniform2f(uniform(program, "depthMapping"), -(farZ + nearZ) / (farZ - nearZ),
              -2.0f * farZ * nearZ / (farZ - nearZ));  // clipping only: the fragment writes linear depth
  glUniform1f(uniform(program, "farDepth"), farZ);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  const float zero[4] = {0, 0, 0, 0};
  for (int i = 0; i < target.targetCount(); ++i) glClearBufferfv(GL_COLOR, i, zero);
  glClear(GL_DEPTH_BUFFER_BIT);
  const GLint albedo = uniform(program, "albedo");
  glUniform1i(uniform(program, "srgbToLinear"), 2);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, scene.srgbToLinear());
  const TimedDraw timed;  // the meshes' draws as one
  for (const GpuScene::MeshGl& m : scene.meshes()) {
    glUniform3f(albedo, m.color.x, m.color.y, m.color.z);
    bindCutout(program, m, 0);
    bindColorTexture(program, m, 1);
    glBindVertexArray(m.vao);
    glDrawElements(GL_TRIANGLES, m.indexCount, GL_UNSIGNED_INT, nullptr);
  }
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
  checkGl("gbuffer");
}

void bindCutout(unsigned program, const GpuScene::MeshGl& mesh, int unit) {
  glUniform1i(uniform(program, "hasCutout"), mesh.cutout != 0 ? 1 : 0);
  glUniform2i(uniform(program, "cutoutWrap"), mesh.cutoutWrap.x, mesh.cutoutWrap.y);
  glUniform1i(uniform(program, "cutout"), unit);
  glActiveTexture(GL_TEXTURE0 + static_cast<unsigned>(unit));
  glBindTexture(GL_TEXTURE_2D, mesh.cutout);
}

void bindColorTexture(unsigned program, const GpuScene::MeshGl& mesh, int unit) {
  glUniform1i(uniform(program, "hasTexture"), mesh.texture != 0 ? 1 : 0);
  glUniform2i(uniform(program, "textureWrap"), mesh.textureWrap.x, mesh.textureWrap.y);
  glUniform1i(uniform(program, "baseColor"), unit);
  glActiveTexture(GL_TEXTURE0 + static_cast<unsigned>(unit));
  glBindTexture(GL_TEXTURE_2D, mesh.texture);
}

void subsampleGBuffer(const GpuScene& scene, const Framebuffer& full, const LevelConstants& level,
                      const Framebuffer& target) {
  const unsigned program = scene.program("gbuffer.subsample", "fullscreen.vert", "gbuffer.frag", "#define SUBSAMPLE\n");
  target.bind();
  glUseProgram(program);
  bindTextures(program, {{"fullPositionHit", full.texture(0)}, {"fullNormalDepth", full.texture(1)},
                         {"fullAlbedo", full.texture(2)}});
  glUniform1i(uniform(program, "scale"), level.scale);
  scene.drawFullscreen();
  checkGl("gbuffer.subsample");
}

void drawLevelGBuffer(const GpuScene& scene, const View& view, const LevelConstants& level, const Framebuffer& target) {
  if (level.scale == 1) {
    drawGBuffer(scene, view, target);
    return;
  }
  const Target g0 = scene.target(level.width * level.scale, level.height * level.scale, 3, true);  // the padded grid
  drawGBuffer(scene, view, *g0);
  subsampleGBuffer(scene, *g0, level, target);
}

GBuffer renderGBuffer(const GpuScene& scene, const View& view, const LevelConstants& level) {
  const Target target = scene.target(level.width, level.height, 3, true);
  drawLevelGBuffer(scene, view, level, *target);
  return readGBuffer(*target);
}

GBuffer readGBuffer(const Framebuffer& target) {
  const ImageF ph = target.read(0), nd = target.read(1), al = target.read(2);
  GBuffer g(target.width(), target.height());
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const bool hit = ph.at(x, y, 3) > 0.5f;
      g.hit.at(x, y) = hit;
      if (!hit) continue;
      g.depth.at(x, y) = nd.at(x, y, 3);
      for (int c = 0; c < 3; ++c) {
        g.position.at(x, y, c) = ph.at(x, y, c);
        g.normal.at(x, y, c) = nd.at(x, y, c);
        g.albedo.at(x, y, c) = al.at(x, y, c);
      }
    }
  return g;
}

}  // namespace mrr::gpu
