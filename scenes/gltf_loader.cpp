#include "scenes/gltf_loader.h"

#include <draco/compression/decode.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <tiny_gltf.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <system_error>

#include "common/error.h"

namespace fs = std::filesystem;

namespace mrr {

namespace {

constexpr int kModePoints = 0;
constexpr int kModeTriangles = 4;
constexpr int kModeStrip = 5;
constexpr int kModeFan = 6;
// A directional light brighter than this (after colour × intensity) is scaled down, keeping
// its hue: glTF intensities are in lux, exporters write anything from 1 to 100,000.
constexpr float kMaxLightScale = 10.0f;
// Credit text taken from ATTRIBUTION.txt spans at most this many lines.
constexpr size_t kMaxCreditLines = 6;
// Deeper node chains than this are garbage (and would exhaust the stack).
constexpr int kMaxNodeDepth = 1000;
// One file is read whole into memory, and tinygltf takes its size as a 32-bit count.
constexpr uintmax_t kMaxFileBytes = 2000000000;
// Counts and offsets in extension objects are JSON numbers: beyond 2^53 they are not exact.
constexpr double kMaxExactInteger = 9007199254740992.0;
// meshoptimizer's codecs expand at most 64:1 (the vertex codec spends 2 bits on 16 zero
// bytes); a stream claiming more than this ratio (plus slack for tiny streams) is corrupt.
constexpr size_t kMeshoptMaxRatio = 256;
constexpr size_t kMeshoptSlack = 256;
// A sparse accessor without a bufferView is zeros that nothing in the file bounds.
constexpr size_t kMaxZeroFilledElements = size_t{1} << 24;
// What a zero element reads from (an accessor element here is at most a FLOAT VEC3).
constexpr unsigned char kZeros[16] = {};
// An alpha-cutout image larger than this many texels is not read (one byte each on both paths).
constexpr int64_t kMaxCutoutTexels = int64_t{1} << 26;  // 8192²

// Required extensions mrr honours: it reads them (lights, compression, quantization), or
// they only change what it ignores anyway (textures and extra material properties).
bool readableExtension(const std::string& ext) {
  return ext == "KHR_lights_punctual" || ext.rfind("KHR_materials_", 0) == 0 || ext.rfind("KHR_texture_", 0) == 0 ||
         ext == "EXT_texture_webp" || ext == "KHR_mesh_quantization" || ext == "EXT_meshopt_compression" ||
         ext == "KHR_draco_mesh_compression";
}

std::string unreadableExtension(const std::string& ext) {
  return "requires glTF extension " + ext + ", which mrr does not read";
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trim(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return {};
  const size_t end = s.find_last_not_of(" \t\r\n");
  return s.substr(begin, end - begin + 1);
}

// tinygltf's messages are several lines; MrrError wants one.
std::string oneLine(const std::string& text) {
  std::string out;
  std::string line;
  for (size_t i = 0; i <= text.size(); ++i) {
    if (i == text.size() || text[i] == '\n' || text[i] == '\r') {
      const std::string t = trim(line);
      if (!t.empty()) out += (out.empty() ? "" : "; ") + t;
      line.clear();
    } else {
      line += text[i];
    }
  }
  return out;
}

const char* modeName(int mode) {
  switch (mode) {
    case 0: return "POINTS";
    case 1: return "LINES";
    case 2: return "LINE_LOOP";
    case 3: return "LINE_STRIP";
    case 4: return "TRIANGLES";
    case 5: return "TRIANGLE_STRIP";
    case 6: return "TRIANGLE_FAN";
    default: return "an unknown mode";
  }
}

const char* componentName(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
    default: return "unknown";
  }
}

size_t componentSize(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return 8;
    default: return 0;
  }
}

const char* typeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "unknown";
  }
}

size_t componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

bool isFinite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// What mrr reads of an image: the alpha where an alpha-MASK material's base colour reads it
// (a cutout), the RGB bytes where a drawn material's base colour does (its albedo); or why it
// could not be decoded. No other image is decoded.
struct ImageAlpha {
  int width = 0, height = 0;
  std::vector<float> alpha;  // width × height, row 0 = the image's first row; 1 where it has none (MASK only)
  std::vector<uint8_t> rgba; // width × height × 4 as stored (sRGB), alpha 255 (base colour only)
  std::string error;         // non-empty: not decoded
};
struct ImageRequests {
  std::set<int> wanted;                // image indices MASK materials need (prepareJson)
  std::set<int> wantedColor;           // image indices drawn materials' base colours need (prepareJson)
  std::map<int, ImageAlpha> decoded;   // filled by decodeWantedImage
};

// tinygltf's image callback: decodes the wanted images' alpha and colour with OpenImageIO,
// from the bytes tinygltf found (a data: URI, a file beside the glTF, or a bufferView); others
// are skipped.
bool decodeWantedImage(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                       const unsigned char* bytes, int size, void* user) {
  auto* requests = static_cast<ImageRequests*>(user);
  const bool wantAlpha = requests && requests->wanted.count(index);
  const bool wantColor = requests && requests->wantedColor.count(index);
  if (!(wantAlpha || wantColor) || size <= 0) return true;
  ImageAlpha& out = requests->decoded[index];
  // OpenImageIO picks its reader by the name's extension: PNG and JPEG are what glTF allows.
  const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG", 4) == 0;
  const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8;
  if (!png && !jpeg) {
    out.error = "neither PNG nor JPEG" + (image->mimeType.empty() ? std::string() : " (" + image->mimeType + ")");
    return true;
  }
  OIIO::Filesystem::IOMemReader reader(const_cast<unsigned char*>(bytes), static_cast<size_t>(size));
  // Colour as stored: OpenImageIO would otherwise premultiply a PNG's colour by its alpha.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::Filesystem::IOProxy* proxy = &reader;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto in = OIIO::ImageInput::open(png ? "image.png" : "image.jpg", wantColor ? &config : nullptr, &reader);
  if (!in) {
    out.error = oneLine(OIIO::geterror());
    return true;
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 ||
      static_cast<int64_t>(spec.width) * spec.height > kMaxCutoutTexels) {
    out.error = std::to_string(spec.width) + "x" + std::to_string(spec.height) + " texels, over the limit of " +
                std::to_string(kMaxCutoutTexels);
    return true;
  }
  out.width = spec.width;
  out.height = spec.height;
  const size_t texels = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height);
  if (!wantColor) {  // a cutout's alpha alone
    out.alpha.assign(texels, 1.0f);
    if (spec.alpha_channel >= 0 &&
        !in->read_image(0, 0, spec.alpha_channel, spec.alpha_channel + 1, OIIO::TypeDesc::FLOAT, out.alpha.data())) {
      out = ImageAlpha{};
      out.error = oneLine(in->geterror());
    }
    return true;
  }
  // Every channel in one read (a PNG cannot be read twice from memory), as float: an 8-bit
  // file's byte b reads b/255, so the bytes come back exactly and the alpha is the one the
  // cutout alone reads. Deeper files round to the nearest byte.
  const int channels = std::max(spec.nchannels, 1);
  std::vector<float> all(texels * static_cast<size_t>(channels));
  if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, all.data())) {
    out = ImageAlpha{};
    out.error = oneLine(in->geterror());
    return true;
  }
  const size_t n = static_cast<size_t>(channels);
  if (wantAlpha) {
    out.alpha.assign(texels, 1.0f);
    if (spec.alpha_channel >= 0 && spec.alpha_channel < channels)
      for (size_t i = 0; i < texels; ++i) out.alpha[i] = all[i * n + static_cast<size_t>(spec.alpha_channel)];
  }
  // RGB; a grey or grey-alpha image's first channel in all three
  const bool grey = channels < 3;
  out.rgba.assign(4 * texels, 255);
  for (size_t i = 0; i < texels; ++i)
    for (size_t c = 0; c < 3; ++c) {
      const float v = all[i * n + (grey ? 0 : c)];
      out.rgba[4 * i + c] = static_cast<uint8_t>(std::lround(std::clamp(v == v ? v : 0.0f, 0.0f, 1.0f) * 255.0f));
    }
  return true;
}

// One primitive, read once per glTF mesh in the mesh's own space, then instanced per node.
struct LocalPrimitive {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty: compute after transforming
  std::vector<uint32_t> indices;   // triangle list
  glm::vec3 baseColor{1.0f};
  int cutout = -1;                   // into Scene::cutouts
  int texture = -1;                  // into Scene::textures
  std::vector<glm::vec2> texcoords;  // with a cutout or a texture only, transformed (materialTexCoord)
  bool blend = false;                // alphaMode BLEND, drawn opaque
};

class Loader {
 public:
  Loader(const std::string& path, const tinygltf::Model& model, const ImageRequests& images, bool quiet, bool skipBlend)
      : path_(path), model_(model), images_(images), quiet_(quiet), skipBlend_(skipBlend) {}

  Scene build() {
    checkRequiredExtensions();
    meshCache_.resize(model_.meshes.size());
    onStack_.assign(model_.nodes.size(), 0);
    for (int root : rootNodes()) visit(root, glm::dmat4(1.0), 0);
    if (skinned_ > 0 || morphed_ > 0)
      warn("skins and morph targets are not applied (" + std::to_string(skinned_) + " skinned mesh nodes, " +
           std::to_string(morphed_) + " primitives with morph targets): rendered in the bind pose");
    warnAlphaModes();
    scene_.name = path_;
    scene_.facts.extensionsRequired = model_.extensionsRequired;
    scene_.facts.extensionsUsed = model_.extensionsUsed;
    for (const tinygltf::Material& material : model_.materials) {
      scene_.facts.maskMaterials += material.alphaMode == "MASK";
      scene_.facts.blendMaterials += material.alphaMode == "BLEND";
      scene_.facts.opaqueMaterials += material.alphaMode != "MASK" && material.alphaMode != "BLEND";
    }
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    throw MrrError(path_ + ": " + message);
  }

  void warn(const std::string& message) const {
    if (!quiet_) std::cerr << "mrr: warning: " << path_ << ": " << message << "\n";
  }

  // Whether the file declares extension `ext` (in extensionsUsed, or only in extensionsRequired).
  bool declares(const std::string& ext) const {
    for (const std::vector<std::string>* list : {&model_.extensionsUsed, &model_.extensionsRequired})
      if (std::find(list->begin(), list->end(), ext) != list->end()) return true;
    return false;
  }

  // prepareJson already refused these before any buffer was read; this covers JSON that
  // only tinygltf could parse.
  void checkRequiredExtensions() const {
    for (const std::string& ext : model_.extensionsRequired)
      if (!readableExtension(ext)) fail(unreadableExtension(ext));
  }

  // One albedo per mesh: BLEND is drawn opaque (or dropped, with --blend-materials skip); MASK
  // is visibility, a cutout (materialCutout).
  bool isBlend(int material) const {
    return material >= 0 && static_cast<size_t>(material) < model_.materials.size() &&
           model_.materials[static_cast<size_t>(material)].alphaMode == "BLEND";
  }
  void warnAlphaModes() const {
    size_t blend = 0;
    for (const tinygltf::Material& material : model_.materials) blend += material.alphaMode == "BLEND";
    if (blend > 0 && skipBlend_)
      warn(std::to_string(blend) + " materials are alphaMode BLEND, skipped (--blend-materials skip): " +
           std::to_string(skippedBlend_) + " primitives left out");
    else if (blend > 0)
      warn(std::to_string(blend) + " materials are alphaMode BLEND, rendered opaque (--blend-materials skip leaves "
           "them out)");
    if (invisiblePrimitives_ > 0)
      warn(std::to_string(invisiblePrimitives_) +
           " primitives are left out: their alphaMode MASK material's alpha is under its cutoff everywhere");
  }

  std::vector<int> rootNodes() const {
    const int sceneCount = static_cast<int>(model_.scenes.size());
    if (sceneCount > 0) {
      const int index =
          (model_.defaultScene >= 0 && model_.defaultScene < sceneCount) ? model_.defaultScene : 0;
      return model_.scenes[static_cast<size_t>(index)].nodes;
    }
    // No scenes: every node that is nobody's child is a root.
    std::vector<char> isChild(model_.nodes.size(), 0);
    for (const tinygltf::Node& node : model_.nodes)
      for (int child : node.children)
        if (child >= 0 && static_cast<size_t>(child) < isChild.size())
          isChild[static_cast<size_t>(child)] = 1;
    std::vector<int> roots;
    for (size_t i = 0; i < model_.nodes.size(); ++i)
      if (!isChild[i]) roots.push_back(static_cast<int>(i));
    return roots;
  }

  glm::dmat4 localMatrix(const tinygltf::Node& node, int index) const {
    const std::string what = "node " + std::to_string(index);
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) fail(what + " matrix has " + std::to_string(node.matrix.size()) + " values, expected 16");
      return glm::make_mat4(node.matrix.data());  // both column-major
    }
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) fail(what + " translation must have 3 values");
      t[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) fail(what + " rotation must have 4 values");
      // glTF stores x, y, z, w; glm's constructor takes w first.
      glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
      const double length = glm::length(q);
      if (!(length > 0.0) || !std::isfinite(length)) fail(what + " rotation is not a valid quaternion");
      r = glm::mat4_cast(q / length);
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) fail(what + " scale must have 3 values");
      s[0][0] = node.scale[0];
      s[1][1] = node.scale[1];
      s[2][2] = node.scale[2];
    }
    return t * r * s;
  }

  void visit(int index, const glm::dmat4& parent, int depth) {
    if (index < 0 || static_cast<size_t>(index) >= model_.nodes.size())
      fail("node index " + std::to_string(index) + " is out of range (" +
           std::to_string(model_.nodes.size()) + " nodes)");
    if (depth > kMaxNodeDepth) fail("node hierarchy is deeper than " + std::to_string(kMaxNodeDepth) + " levels");
    const size_t i = static_cast<size_t>(index);
    if (onStack_[i]) fail("node " + std::to_string(index) + " is its own ancestor (cycle in the node hierarchy)");
    onStack_[i] = 1;
    const tinygltf::Node& node = model_.nodes[i];
    const glm::dmat4 world = parent * localMatrix(node, index);
    for (int c = 0; c < 16; ++c)
      if (!std::isfinite(world[c / 4][c % 4])) fail("node " + std::to_string(index) + " has a non-finite transform");

    if (node.mesh >= 0) addMeshInstance(node.mesh, world);
    if (node.mesh >= 0 && node.skin >= 0) ++skinned_;
    else if (node.mesh < -1) fail("node " + std::to_string(index) + " mesh index " + std::to_string(node.mesh) + " is invalid");
    if (node.camera != -1) addCamera(node, world);
    readLight(node, world);
    for (int child : node.children) visit(child, world, depth + 1);
    onStack_[i] = 0;
  }

  // ---- buffer views and accessors ----------------------------------------------------------

  // A bufferView's bytes: a checked range of its buffer, or the data EXT_meshopt_compression
  // decodes for it (decoded once and kept while the loader runs).
  struct Bytes {
    const unsigned char* data = nullptr;
    size_t size = 0;
  };

  static bool isMeshoptFallback(const tinygltf::Buffer& buffer) {
    const auto ext = buffer.extensions.find("EXT_meshopt_compression");
    return ext != buffer.extensions.end() && ext->second.Get("fallback").IsBool() &&
           ext->second.Get("fallback").Get<bool>();
  }

  const tinygltf::Buffer& bufferAt(int index, const std::string& where) const {
    if (index < 0 || static_cast<size_t>(index) >= model_.buffers.size())
      fail(where + " names buffer " + std::to_string(index) + ", which does not exist");
    const tinygltf::Buffer& buffer = model_.buffers[static_cast<size_t>(index)];
    // The fallback was replaced by a placeholder before parsing (prepareJson): its data is
    // only ever reached through a compressed view, never directly.
    if (isMeshoptFallback(buffer))
      fail(where + " reads buffer " + std::to_string(index) +
           ", an EXT_meshopt_compression fallback that holds no data");
    return buffer;
  }

  Bytes viewBytes(int index, const std::string& where) const {
    if (index < 0 || static_cast<size_t>(index) >= model_.bufferViews.size())
      fail(where + " has no valid bufferView (" + std::to_string(index) + ")");
    const tinygltf::BufferView& bufferView = model_.bufferViews[static_cast<size_t>(index)];
    const auto meshopt = bufferView.extensions.find("EXT_meshopt_compression");
    if (meshopt != bufferView.extensions.end()) {
      const std::vector<unsigned char>& decoded = decodeMeshopt(index, meshopt->second);
      return {decoded.data(), decoded.size()};
    }
    const std::string name = "bufferView " + std::to_string(index);
    const tinygltf::Buffer& buffer = bufferAt(bufferView.buffer, where + " " + name);
    const size_t bufferSize = buffer.data.size();
    if (bufferView.byteOffset > bufferSize || bufferView.byteLength > bufferSize - bufferView.byteOffset)
      fail(where + " " + name + " (offset " + std::to_string(bufferView.byteOffset) + ", length " +
           std::to_string(bufferView.byteLength) + ") runs past the end of buffer " +
           std::to_string(bufferView.buffer) + " (" + std::to_string(bufferSize) + " bytes)");
    return {buffer.data.data() + bufferView.byteOffset, bufferView.byteLength};
  }

  // A non-negative integer member of an extension object; `fallback` when absent, if given.
  size_t extensionCount(const tinygltf::Value& object, const char* key, const std::string& where,
                        std::optional<size_t> fallback = std::nullopt) const {
    if (!object.Has(key)) {
      if (fallback) return *fallback;
      fail(where + " has no '" + key + "'");
    }
    const tinygltf::Value& value = object.Get(key);
    const double number = value.IsNumber() ? value.GetNumberAsDouble() : -1.0;
    if (!(number >= 0.0 && number <= kMaxExactInteger) || std::floor(number) != number)
      fail(where + " '" + key + "' is not a valid count or offset");
    return static_cast<size_t>(number);
  }

  std::string extensionString(const tinygltf::Value& object, const char* key, const std::string& fallback) const {
    if (!object.Has(key) || !object.Get(key).IsString()) return fallback;
    return object.Get(key).Get<std::string>();
  }

  // EXT_meshopt_compression: the view's data is `count` elements of `byteStride` bytes, coded
  // in a range of another buffer. Every parameter the decoders assert on is checked first;
  // the decoders themselves reject corrupt streams with a non-zero status.
  const std::vector<unsigned char>& decodeMeshopt(int index, const tinygltf::Value& ext) const {
    const auto cached = decoded_.find(index);
    if (cached != decoded_.end()) return cached->second;
    const std::string where = "bufferView " + std::to_string(index) + " (EXT_meshopt_compression)";
    if (!ext.IsObject()) fail(where + " is not an object");
    const size_t bufferIndex = extensionCount(ext, "buffer", where);
    const size_t byteOffset = extensionCount(ext, "byteOffset", where, 0);
    const size_t byteLength = extensionCount(ext, "byteLength", where);
    const size_t stride = extensionCount(ext, "byteStride", where);
    const size_t count = extensionCount(ext, "count", where);
    const std::string mode = extensionString(ext, "mode", "");
    const std::string filter = extensionString(ext, "filter", "NONE");
    const tinygltf::Buffer& buffer =
        bufferAt(bufferIndex > INT32_MAX ? -1 : static_cast<int>(bufferIndex), where);
    if (byteOffset > buffer.data.size() || byteLength > buffer.data.size() - byteOffset)
      fail(where + " (offset " + std::to_string(byteOffset) + ", length " + std::to_string(byteLength) +
           ") runs past the end of buffer " + std::to_string(bufferIndex) + " (" +
           std::to_string(buffer.data.size()) + " bytes)");

    const bool attributes = mode == "ATTRIBUTES";
    if (attributes) {
      if (stride == 0 || stride > 256 || stride % 4 != 0)
        fail(where + " byteStride " + std::to_string(stride) + " must be a multiple of 4 up to 256 for ATTRIBUTES");
    } else if (mode == "TRIANGLES" || mode == "INDICES") {
      if (stride != 2 && stride != 4) fail(where + " byteStride " + std::to_string(stride) + " must be 2 or 4 for " + mode);
      if (mode == "TRIANGLES" && count % 3 != 0)
        fail(where + " count " + std::to_string(count) + " is not a multiple of 3 for TRIANGLES");
    } else {
      fail(where + " has unknown mode '" + mode + "'");
    }
    const bool filterFits = filter == "NONE" || (attributes && filter == "OCTAHEDRAL" && (stride == 4 || stride == 8)) ||
                            (attributes && filter == "QUATERNION" && stride == 8) ||
                            (attributes && filter == "EXPONENTIAL");
    if (!filterFits) fail(where + " filter '" + filter + "' does not apply to " + mode + " with byteStride " + std::to_string(stride));
    // No codec expands data more than 64:1 (the vertex codec spends 2 bits on 16 zero bytes):
    // a larger claim is a corrupt file, refused before it allocates.
    if (count > (byteLength + kMeshoptSlack) * kMeshoptMaxRatio / stride)
      fail(where + " claims " + std::to_string(count) + " elements of " + std::to_string(stride) +
           " bytes from " + std::to_string(byteLength) + " compressed bytes; the data is corrupt");

    std::vector<unsigned char> out(count * stride);
    if (count > 0) {
      const unsigned char* source = buffer.data.data() + byteOffset;
      const int status = attributes ? meshopt_decodeVertexBuffer(out.data(), count, stride, source, byteLength)
                         : mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, source, byteLength)
                                               : meshopt_decodeIndexSequence(out.data(), count, stride, source, byteLength);
      if (status != 0)
        fail(where + ": the " + mode + " data is corrupt (meshoptimizer's decoder returned " +
             std::to_string(status) + ")");
      if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), count, stride);
      else if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), count, stride);
      else if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), count, stride);
    }
    return decoded_.emplace(index, std::move(out)).first->second;
  }

  // The start of `count` elements of `elementSize` bytes, `stride` apart, from `byteOffset`
  // into `bytes`: reading them stays inside (computed without overflow).
  const unsigned char* locate(const Bytes& bytes, size_t byteOffset, size_t count, size_t elementSize,
                              size_t stride, const std::string& where) const {
    if (count == 0) return bytes.data;
    const size_t available = bytes.size;
    const bool fits = byteOffset <= available && elementSize <= available - byteOffset &&
                      count - 1 <= (available - byteOffset - elementSize) / stride;
    if (!fits)
      fail(where + " needs " + std::to_string(count) + " elements of " + std::to_string(elementSize) +
           " bytes from offset " + std::to_string(byteOffset) + " but its bufferView holds only " +
           std::to_string(available) + " bytes");
    return bytes.data + byteOffset;
  }

  // Where each element of an accessor lies, every range checked: in its bufferView, in the
  // sparse values where glTF 2.0 §3.6.2.3 substitutes it, or in zeros (a sparse accessor
  // without a bufferView).
  std::vector<const unsigned char*> elements(int accessorIndex, const std::string& what) const {
    if (accessorIndex < 0 || static_cast<size_t>(accessorIndex) >= model_.accessors.size())
      fail(what + " accessor " + std::to_string(accessorIndex) + " is out of range (" +
           std::to_string(model_.accessors.size()) + " accessors)");
    const tinygltf::Accessor& accessor = model_.accessors[static_cast<size_t>(accessorIndex)];
    const std::string where = what + " (accessor " + std::to_string(accessorIndex) + ")";
    const size_t elementSize = componentSize(accessor.componentType) * componentCount(accessor.type);
    if (elementSize == 0) fail(where + " has an invalid componentType or type");
    if (elementSize > sizeof kZeros) fail(where + " has elements of " + std::to_string(elementSize) + " bytes");

    std::vector<const unsigned char*> out;
    if (accessor.bufferView >= 0 || !accessor.sparse.isSparse) {
      const Bytes bytes = viewBytes(accessor.bufferView, where);
      const size_t viewStride = model_.bufferViews[static_cast<size_t>(accessor.bufferView)].byteStride;
      const size_t stride = viewStride != 0 ? viewStride : elementSize;
      if (stride < elementSize)
        fail(where + " byteStride " + std::to_string(stride) + " is smaller than its element size " +
             std::to_string(elementSize));
      const unsigned char* base = locate(bytes, accessor.byteOffset, accessor.count, elementSize, stride, where);
      out.resize(accessor.count);
      for (size_t i = 0; i < accessor.count; ++i) out[i] = base + i * stride;
    } else {
      // All zeros but the substitutions: nothing in the file bounds the count, so we do.
      if (accessor.count > kMaxZeroFilledElements)
        fail(where + " is sparse without a bufferView and claims " + std::to_string(accessor.count) +
             " elements, over the limit of " + std::to_string(kMaxZeroFilledElements));
      out.assign(accessor.count, kZeros);
    }
    if (accessor.sparse.isSparse) substituteSparse(accessor, elementSize, out, where);
    return out;
  }

  void substituteSparse(const tinygltf::Accessor& accessor, size_t elementSize,
                        std::vector<const unsigned char*>& out, const std::string& where) const {
    const auto& sparse = accessor.sparse;
    const std::string what = where + " sparse";
    if (sparse.count < 1 || static_cast<size_t>(sparse.count) > out.size())
      fail(what + " count " + std::to_string(sparse.count) + " is not between 1 and the accessor's " +
           std::to_string(out.size()) + " elements");
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) fail(what + " has a negative byteOffset");
    const int ct = sparse.indices.componentType;
    const size_t indexSize = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                             : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                             : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                            : 0;
    if (indexSize == 0)
      fail(what + " indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not " + componentName(ct));
    const size_t count = static_cast<size_t>(sparse.count);
    // Both arrays are tightly packed (§3.6.2.3: their bufferViews have no byteStride).
    const unsigned char* indices = locate(viewBytes(sparse.indices.bufferView, what + " indices"),
                                          static_cast<size_t>(sparse.indices.byteOffset), count, indexSize,
                                          indexSize, what + " indices");
    const unsigned char* values = locate(viewBytes(sparse.values.bufferView, what + " values"),
                                         static_cast<size_t>(sparse.values.byteOffset), count, elementSize,
                                         elementSize, what + " values");
    for (size_t i = 0; i < count; ++i) {
      const auto target = static_cast<size_t>(component(indices + i * indexSize, ct, false));
      if (target >= out.size())
        fail(what + " index " + std::to_string(target) + " is out of range (" + std::to_string(out.size()) +
             " elements)");
      out[target] = values + i * elementSize;
    }
  }

  // One component as a number; normalized integers map to [-1, 1] or [0, 1] (glTF 2.0 §3.11).
  static double component(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t v;
        std::memcpy(&v, p, sizeof v);
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        std::memcpy(&v, p, sizeof v);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, sizeof v);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, p, sizeof v);
        return normalized ? v / 4294967295.0 : v;
      }
      default: {  // FLOAT: the callers accept no other type
        float v;
        std::memcpy(&v, p, sizeof v);  // no alignment assumptions
        return v;
      }
    }
  }

  // FLOAT, or with KHR_mesh_quantization (signed or unsigned, normalized or not) BYTE and
  // SHORT VEC3 (VEC2 for texture coordinates); the node transform then scales positions as
  // usual. Non-finite values are an error, but for normals (exporters write NaN for the normal
  // of a degenerate face), which are allowed here and repaired from the geometry later.
  // An integer type in a file that does not declare KHR_mesh_quantization is an error (read,
  // it would be garbage geometry): but for texture coordinates, which glTF 2.0 itself allows as
  // normalized UNSIGNED_BYTE and UNSIGNED_SHORT (§3.7.2.1). Files EXT_meshopt_compression
  // quantizes declare the extension too (its spec requires it).
  template <int N>
  std::vector<glm::vec<N, float>> readVec(int accessorIndex, const std::string& what, bool allowNonFinite = false) const {
    const tinygltf::Accessor* accessor =
        (accessorIndex >= 0 && static_cast<size_t>(accessorIndex) < model_.accessors.size())
            ? &model_.accessors[static_cast<size_t>(accessorIndex)]
            : nullptr;
    int ct = TINYGLTF_COMPONENT_TYPE_FLOAT;
    bool normalized = false;
    const std::string type = N == 2 ? "VEC2" : "VEC3";
    if (accessor) {
      ct = accessor->componentType;
      normalized = accessor->normalized;
      const bool okType = ct == TINYGLTF_COMPONENT_TYPE_FLOAT || ct == TINYGLTF_COMPONENT_TYPE_BYTE ||
                          ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || ct == TINYGLTF_COMPONENT_TYPE_SHORT ||
                          ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
      if (!okType || accessor->type != (N == 2 ? TINYGLTF_TYPE_VEC2 : TINYGLTF_TYPE_VEC3))
        fail(what + " (accessor " + std::to_string(accessorIndex) + ") must be FLOAT " + type + ", or BYTE or SHORT " +
             type + " (KHR_mesh_quantization), not " + componentName(accessor->componentType) + " " +
             typeName(accessor->type));
      const bool coreTexcoord =
          N == 2 && normalized && (ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
      if (ct != TINYGLTF_COMPONENT_TYPE_FLOAT && !coreTexcoord && !declares("KHR_mesh_quantization"))
        fail(what + " accessor " + std::to_string(accessorIndex) + " has componentType " + componentName(ct) +
             (normalized ? " (normalized)" : "") +
             ", which needs KHR_mesh_quantization (not declared in extensionsUsed or extensionsRequired)");
    }
    const std::vector<const unsigned char*> at = elements(accessorIndex, what);
    const size_t size = componentSize(ct);
    std::vector<glm::vec<N, float>> out(at.size());
    for (size_t i = 0; i < at.size(); ++i) {
      bool finite = true;
      for (int c = 0; c < N; ++c) {
        out[i][c] = static_cast<float>(component(at[i] + static_cast<size_t>(c) * size, ct, normalized));
        finite = finite && std::isfinite(out[i][c]);
      }
      if (!allowNonFinite && !finite) {
        std::string values;
        for (int c = 0; c < N; ++c) values += (c ? ", " : "") + std::to_string(out[i][c]);
        fail(what + " element " + std::to_string(i) + " is not finite (" + values + ")");
      }
    }
    return out;
  }
  std::vector<glm::vec3> readVec3(int accessorIndex, const std::string& what, bool allowNonFinite = false) const {
    return readVec<3>(accessorIndex, what, allowNonFinite);
  }

  std::vector<uint32_t> readIndices(int accessorIndex, const std::string& what) const {
    const tinygltf::Accessor* accessor =
        (accessorIndex >= 0 && static_cast<size_t>(accessorIndex) < model_.accessors.size())
            ? &model_.accessors[static_cast<size_t>(accessorIndex)]
            : nullptr;
    if (accessor) {
      const int ct = accessor->componentType;
      const bool okType = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                          ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
                          ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
      if (!okType || accessor->type != TINYGLTF_TYPE_SCALAR)
        fail(what + " (accessor " + std::to_string(accessorIndex) +
             ") must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT SCALAR, not " +
             componentName(ct) + " " + typeName(accessor->type));
    }
    const std::vector<const unsigned char*> at = elements(accessorIndex, what);
    const int ct = model_.accessors[static_cast<size_t>(accessorIndex)].componentType;
    std::vector<uint32_t> out(at.size());
    for (size_t i = 0; i < at.size(); ++i) out[i] = static_cast<uint32_t>(component(at[i], ct, false));
    return out;
  }

  // KHR_draco_mesh_compression: the primitive's triangles and attributes are one Draco mesh in
  // a bufferView; the extension maps glTF attribute names to Draco attribute ids. Draco
  // returns a status for corrupt data; values and ids are checked here before use.
  void decodeDraco(const tinygltf::Value& ext, bool wantNormals, const std::string& texcoordName,
                   const std::string& what, LocalPrimitive& out, std::vector<uint32_t>& indices) const {
    const std::string where = what + " (KHR_draco_mesh_compression)";
    if (!ext.IsObject() || !ext.Get("attributes").IsObject()) fail(where + " has no 'attributes' object");
    const size_t viewIndex = extensionCount(ext, "bufferView", where);
    const Bytes bytes = viewBytes(viewIndex > INT32_MAX ? -1 : static_cast<int>(viewIndex), where);
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data), bytes.size);
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok())
      fail(where + ": the data is corrupt (Draco: " + oneLine(decoded.status().error_msg_string()) + ")");
    const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
    if (!mesh) fail(where + ": Draco decoded no mesh");
    const tinygltf::Value& attributes = ext.Get("attributes");
    out.positions = dracoVec3(*mesh, attributes, "POSITION", where, false);
    // A NORMAL the primitive lists but the Draco attributes lack is an error like any other.
    if (wantNormals || attributes.Has("NORMAL")) out.normals = dracoVec3(*mesh, attributes, "NORMAL", where, true);
    if (!texcoordName.empty() && attributes.Has(texcoordName))
      out.texcoords = dracoVec<2>(*mesh, attributes, texcoordName.c_str(), where, false);
    indices.resize(3 * static_cast<size_t>(mesh->num_faces()));
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
      const draco::Mesh::Face& face = mesh->face(f);
      for (size_t c = 0; c < 3; ++c) indices[3 * static_cast<size_t>(f.value()) + c] = face[c].value();
    }
  }

  std::vector<glm::vec3> dracoVec3(const draco::Mesh& mesh, const tinygltf::Value& attributes, const char* name,
                                   const std::string& where, bool allowNonFinite) const {
    return dracoVec<3>(mesh, attributes, name, where, allowNonFinite);
  }
  template <int N>
  std::vector<glm::vec<N, float>> dracoVec(const draco::Mesh& mesh, const tinygltf::Value& attributes, const char* name,
                                           const std::string& where, bool allowNonFinite) const {
    const size_t id = extensionCount(attributes, name, where + " attributes");
    const draco::PointAttribute* attribute =
        id > UINT32_MAX ? nullptr : mesh.GetAttributeByUniqueId(static_cast<uint32_t>(id));
    if (!attribute)
      fail(where + " " + name + " is Draco attribute " + std::to_string(id) + ", which the data does not hold");
    if (attribute->num_components() != N)
      fail(where + " " + name + " has " + std::to_string(attribute->num_components()) + " components, expected " +
           std::to_string(N));
    std::vector<glm::vec<N, float>> out(mesh.num_points());
    for (draco::PointIndex p(0); p < mesh.num_points(); ++p) {
      const draco::AttributeValueIndex value = attribute->mapped_index(p);
      float xyz[N];
      if (value.value() >= attribute->size() || !attribute->ConvertValue<float>(value, N, xyz))
        fail(where + " " + name + " of point " + std::to_string(p.value()) + " cannot be read");
      bool finite = true;
      for (int c = 0; c < N; ++c) {
        out[p.value()][c] = xyz[c];
        finite = finite && std::isfinite(xyz[c]);
      }
      if (!allowNonFinite && !finite)
        fail(where + " " + name + " of point " + std::to_string(p.value()) + " is not finite");
    }
    return out;
  }

  // ---- meshes ----------------------------------------------------------------------------

  // ---- alpha cutouts (docs/spec.md §1.1) ----------------------------------------------------

  struct MaterialCutout {
    int cutout = -1;         // into scene_.cutouts: the primitive is cut out by it
    bool invisible = false;  // every texel (or the factor alone) is under the cutoff: not drawn
    int texCoord = 0;        // which TEXCOORD_n the cutout reads
  };

  // What a material's alpha does to visibility. Only alphaMode MASK does anything: alpha = the
  // base-colour factor's alpha × its texture's alpha, opaque where alpha ≥ alphaCutoff (glTF 2.0
  // §3.9.4). Decided once per material, on the host, into one bit per texel: both paths then
  // read the same bits. A MASK whose image cannot be read is drawn opaque, said once.
  const MaterialCutout& materialCutout(int material) {
    const auto cached = cutouts_.find(material);
    if (cached != cutouts_.end()) return cached->second;
    MaterialCutout& out = cutouts_[material];
    if (material < 0 || static_cast<size_t>(material) >= model_.materials.size()) return out;
    const tinygltf::Material& m = model_.materials[static_cast<size_t>(material)];
    if (m.alphaMode != "MASK") return out;
    const std::string name = "material " + (m.name.empty() ? std::to_string(material) : "'" + m.name + "'");
    const std::vector<double>& factor = m.pbrMetallicRoughness.baseColorFactor;
    const float factorAlpha =
        factor.size() == 4 && std::isfinite(factor[3]) ? static_cast<float>(std::clamp(factor[3], 0.0, 1.0)) : 1.0f;
    const float cutoff = std::isfinite(m.alphaCutoff) ? static_cast<float>(m.alphaCutoff) : 0.5f;
    const tinygltf::TextureInfo& info = m.pbrMetallicRoughness.baseColorTexture;
    if (info.index < 0) {  // the factor alone: all or nothing
      out.invisible = !(factorAlpha >= cutoff);
      return out;
    }
    if (static_cast<size_t>(info.index) >= model_.textures.size()) {
      warn(name + " (alpha MASK): base-colour texture " + std::to_string(info.index) +
           " is out of range: drawn without its cutout");
      return out;
    }
    const tinygltf::Texture& texture = model_.textures[static_cast<size_t>(info.index)];
    const int source = textureSource(texture);
    const auto image = images_.decoded.find(source);
    if (image == images_.decoded.end() || !image->second.error.empty()) {
      const std::string why = image == images_.decoded.end() ? "could not be read (see above)" : image->second.error;
      warn(name + " (alpha MASK): base-colour image " + std::to_string(source) + " " + why +
           ": drawn without its cutout");
      return out;
    }
    const ImageAlpha& alpha = image->second;
    Cutout cutout;
    cutout.width = alpha.width;
    cutout.height = alpha.height;
    cutout.opaque.resize(alpha.alpha.size());
    size_t opaque = 0;
    for (size_t i = 0; i < alpha.alpha.size(); ++i) {
      cutout.opaque[i] = factorAlpha * alpha.alpha[i] >= cutoff ? 1 : 0;
      opaque += cutout.opaque[i];
    }
    if (texture.sampler >= 0 && static_cast<size_t>(texture.sampler) < model_.samplers.size()) {
      const tinygltf::Sampler& sampler = model_.samplers[static_cast<size_t>(texture.sampler)];
      cutout.wrapS = wrapOf(sampler.wrapS);
      cutout.wrapT = wrapOf(sampler.wrapT);
    }
    out.texCoord = materialTexCoord(material).index;
    if (opaque == 0) {
      out.invisible = true;
    } else if (opaque < cutout.opaque.size()) {
      out.cutout = static_cast<int>(scene_.cutouts.size());
      scene_.cutouts.push_back(std::move(cutout));
    }
    return out;
  }

  // ---- base-colour textures (docs/spec.md §1.2) ----------------------------------------------

  // Which TEXCOORD_n a material's base-colour texture reads, and KHR_texture_transform's affine
  // map of it: (s', t') = offset + R(rotation) · (scale ⊙ (s, t)), glTF's T · R · S.
  struct TexCoord {
    int index = 0;
    bool transformed = false;
    double m[2][3] = {{1, 0, 0}, {0, 1, 0}};  // s' = m[0]·(s, t, 1), t' = m[1]·(s, t, 1)
  };
  TexCoord materialTexCoord(int material) const {
    TexCoord out;
    if (material < 0 || static_cast<size_t>(material) >= model_.materials.size()) return out;
    const tinygltf::TextureInfo& info = model_.materials[static_cast<size_t>(material)].pbrMetallicRoughness.baseColorTexture;
    out.index = std::max(info.texCoord, 0);
    const auto ext = info.extensions.find("KHR_texture_transform");
    if (ext == info.extensions.end() || !ext->second.IsObject()) return out;
    const tinygltf::Value& t = ext->second;
    auto number = [](const tinygltf::Value& v, double fallback) {
      return v.IsNumber() && std::isfinite(v.GetNumberAsDouble()) ? v.GetNumberAsDouble() : fallback;
    };
    auto pair = [&](const char* key, double fallback, double& a, double& b) {
      const tinygltf::Value& v = t.Get(key);
      a = b = fallback;
      if (v.IsArray() && v.ArrayLen() == 2) {
        a = number(v.Get(0), fallback);
        b = number(v.Get(1), fallback);
      }
    };
    double ox, oy, sx, sy;
    pair("offset", 0.0, ox, oy);
    pair("scale", 1.0, sx, sy);
    const double r = number(t.Get("rotation"), 0.0);
    if (t.Get("texCoord").IsInt()) out.index = std::max(t.Get("texCoord").GetNumberAsInt(), 0);
    // KHR_texture_transform: rotation [[c, s], [−s, c]] (counter-clockwise in UV space)
    const double c = std::cos(r), sn = std::sin(r);
    out.m[0][0] = c * sx;
    out.m[0][1] = sn * sy;
    out.m[0][2] = ox;
    out.m[1][0] = -sn * sx;
    out.m[1][1] = c * sy;
    out.m[1][2] = oy;
    out.transformed = true;
    return out;
  }
  static void applyTexCoord(const TexCoord& tc, std::vector<glm::vec2>& st) {
    if (!tc.transformed) return;
    for (glm::vec2& p : st) {
      const double s = p.x, t = p.y;
      p = glm::vec2(static_cast<float>(tc.m[0][0] * s + tc.m[0][1] * t + tc.m[0][2]),
                    static_cast<float>(tc.m[1][0] * s + tc.m[1][1] * t + tc.m[1][2]));
    }
  }

  // A material's base-colour texture as a Scene::textures index (one per glTF texture, shared
  // by the materials that use it), or -1: none, or its image could not be read (said once).
  int materialTexture(int material) {
    const auto cached = textures_.find(material);
    if (cached != textures_.end()) return cached->second;
    int& out = textures_[material];
    out = -1;
    if (material < 0 || static_cast<size_t>(material) >= model_.materials.size()) return out;
    const tinygltf::Material& m = model_.materials[static_cast<size_t>(material)];
    const tinygltf::TextureInfo& info = m.pbrMetallicRoughness.baseColorTexture;
    if (info.index < 0) return out;
    const std::string name = "material " + (m.name.empty() ? std::to_string(material) : "'" + m.name + "'");
    if (static_cast<size_t>(info.index) >= model_.textures.size()) {
      warn(name + ": base-colour texture " + std::to_string(info.index) + " is out of range: drawn with its factor");
      return out;
    }
    const auto shared = textureIndex_.find(info.index);
    if (shared != textureIndex_.end()) return out = shared->second;
    const tinygltf::Texture& texture = model_.textures[static_cast<size_t>(info.index)];
    const int source = textureSource(texture);
    const auto image = images_.decoded.find(source);
    if (image == images_.decoded.end() || !image->second.error.empty() || image->second.rgba.empty()) {
      const std::string why = image == images_.decoded.end() || image->second.error.empty()
                                  ? "could not be read (see above)"
                                  : image->second.error;
      warn(name + ": base-colour image " + std::to_string(source) + " " + why + ": drawn with its factor");
      return out;
    }
    ColorTexture colour;
    colour.width = image->second.width;
    colour.height = image->second.height;
    colour.rgba = image->second.rgba;
    if (texture.sampler >= 0 && static_cast<size_t>(texture.sampler) < model_.samplers.size()) {
      const tinygltf::Sampler& sampler = model_.samplers[static_cast<size_t>(texture.sampler)];
      colour.wrapS = wrapOf(sampler.wrapS);
      colour.wrapT = wrapOf(sampler.wrapT);
    }
    out = static_cast<int>(scene_.textures.size());
    textureIndex_[info.index] = out;
    scene_.textures.push_back(std::move(colour));
    return out;
  }

  // A texture's image: its source, or an EXT_texture_webp source when it has none.
  static int textureSource(const tinygltf::Texture& texture) {
    if (texture.source >= 0) return texture.source;
    const auto webp = texture.extensions.find("EXT_texture_webp");
    if (webp != texture.extensions.end() && webp->second.IsObject() && webp->second.Get("source").IsInt())
      return webp->second.Get("source").GetNumberAsInt();
    return -1;
  }

  static Wrap wrapOf(int glWrap) {
    if (glWrap == 33071) return Wrap::Clamp;   // CLAMP_TO_EDGE
    if (glWrap == 33648) return Wrap::Mirror;  // MIRRORED_REPEAT
    return Wrap::Repeat;                       // REPEAT, and the default
  }

  glm::vec3 materialColor(int material, const std::string& what) const {
    if (material == -1) return glm::vec3(1.0f);
    if (material < 0 || static_cast<size_t>(material) >= model_.materials.size())
      fail(what + " material " + std::to_string(material) + " is out of range (" +
           std::to_string(model_.materials.size()) + " materials)");
    // The factor; its base-colour texture, if any, is materialTexture.
    const std::vector<double>& factor =
        model_.materials[static_cast<size_t>(material)].pbrMetallicRoughness.baseColorFactor;
    glm::vec3 color(1.0f);
    for (int c = 0; c < 3 && static_cast<size_t>(c) < factor.size(); ++c) {
      const double value = factor[static_cast<size_t>(c)];
      color[c] = std::isfinite(value) ? static_cast<float>(std::clamp(value, 0.0, 1.0)) : 1.0f;
    }
    return color;
  }

  static std::vector<uint32_t> toTriangleList(int mode, const std::vector<uint32_t>& in) {
    std::vector<uint32_t> out;
    if (mode == kModeTriangles) {
      out.assign(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(in.size() / 3 * 3));
    } else if (mode == kModeStrip) {
      // glTF 2.0 §3.7.2.1: odd triangles swap their first two vertices to keep the winding.
      for (size_t i = 0; i + 2 < in.size(); ++i) {
        if (i % 2 == 0) out.insert(out.end(), {in[i], in[i + 1], in[i + 2]});
        else out.insert(out.end(), {in[i + 1], in[i], in[i + 2]});
      }
    } else {  // fan
      for (size_t i = 1; i + 1 < in.size(); ++i) out.insert(out.end(), {in[i], in[i + 1], in[0]});
    }
    return out;
  }

  const std::vector<LocalPrimitive>& meshPrimitives(int meshIndex) {
    if (static_cast<size_t>(meshIndex) >= model_.meshes.size())
      fail("mesh index " + std::to_string(meshIndex) + " is out of range (" +
           std::to_string(model_.meshes.size()) + " meshes)");
    std::optional<std::vector<LocalPrimitive>>& cached = meshCache_[static_cast<size_t>(meshIndex)];
    if (cached) return *cached;
    cached.emplace();
    const tinygltf::Mesh& mesh = model_.meshes[static_cast<size_t>(meshIndex)];
    const std::string meshName = mesh.name.empty() ? "mesh" + std::to_string(meshIndex) : mesh.name;
    for (size_t k = 0; k < mesh.primitives.size(); ++k) {
      const tinygltf::Primitive& primitive = mesh.primitives[k];
      const std::string what = "mesh '" + meshName + "' primitive " + std::to_string(k);
      const int mode = primitive.mode == -1 ? kModeTriangles : primitive.mode;
      if (mode >= kModePoints && mode < kModeTriangles) {
        warn(what + " is " + modeName(mode) + ", skipped");
        continue;
      }
      if (mode != kModeTriangles && mode != kModeStrip && mode != kModeFan)
        fail(what + " has unknown mode " + std::to_string(mode));
      if (skipBlend_ && isBlend(primitive.material)) {
        ++skippedBlend_;
        continue;
      }
      const MaterialCutout& cut = materialCutout(primitive.material);
      if (cut.invisible) {  // alpha MASK whose alpha is under the cutoff everywhere
        ++invisiblePrimitives_;
        continue;
      }
      const int texture = materialTexture(primitive.material);
      const bool wantTexcoords = cut.cutout >= 0 || texture >= 0;
      const TexCoord texCoord = materialTexCoord(primitive.material);
      const std::string texcoordName = "TEXCOORD_" + std::to_string(texCoord.index);
      const auto position = primitive.attributes.find("POSITION");
      if (position == primitive.attributes.end()) fail(what + " has no POSITION attribute");

      LocalPrimitive out;
      out.name = meshName + "/" + std::to_string(k);
      if (!primitive.targets.empty()) ++morphed_;
      const auto draco = primitive.extensions.find("KHR_draco_mesh_compression");
      const bool compressed = draco != primitive.extensions.end();
      std::vector<uint32_t> indices;
      const auto normal = primitive.attributes.find("NORMAL");
      if (compressed) {
        if (mode != kModeTriangles)
          fail(what + " is a Draco-compressed " + modeName(mode) + "; mrr reads Draco TRIANGLES only");
        decodeDraco(draco->second, normal != primitive.attributes.end(), wantTexcoords ? texcoordName : "", what,
                    out, indices);
      } else {
        out.positions = readVec3(position->second, what + " POSITION");
        if (normal != primitive.attributes.end()) out.normals = readVec3(normal->second, what + " NORMAL", true);
        const auto texcoord = primitive.attributes.find(texcoordName);
        if (wantTexcoords && texcoord != primitive.attributes.end())
          out.texcoords = readVec<2>(texcoord->second, what + " " + texcoordName);
      }
      if (wantTexcoords) {
        if (out.texcoords.size() == out.positions.size()) {
          applyTexCoord(texCoord, out.texcoords);
          out.cutout = cut.cutout;
          out.texture = texture;
        } else {
          warn(what + ": its material's base-colour texture reads " + texcoordName + ", which the primitive " +
               (out.texcoords.empty() ? "lacks" : "has for " + std::to_string(out.texcoords.size()) + " of " +
                                                      std::to_string(out.positions.size()) + " vertices") +
               (cut.cutout >= 0 ? ": drawn without the cutout" : ": drawn with its factor"));
          out.texcoords.clear();
        }
      }
      if (!out.normals.empty()) {
        if (out.normals.size() != out.positions.size())
          fail(what + " has " + std::to_string(out.normals.size()) + " normals for " +
               std::to_string(out.positions.size()) + " positions");
        const auto broken = std::count_if(out.normals.begin(), out.normals.end(), [](const glm::vec3& n) {
          return !isFinite(glm::dvec3(n)) || !(glm::length(n) > 0.0f);
        });
        if (broken > 0)
          warn(what + " has " + std::to_string(broken) + " zero or non-finite normals, replaced by computed ones");
      }
      if (compressed) {
        // The triangles came with the Draco mesh.
      } else if (primitive.indices >= 0) {
        indices = readIndices(primitive.indices, what + " indices");
      } else {
        if (out.positions.size() > UINT32_MAX) fail(what + " has too many vertices");
        indices.resize(out.positions.size());
        for (size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<uint32_t>(i);
      }
      for (size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= out.positions.size())
          fail(what + " index " + std::to_string(indices[i]) + " (at " + std::to_string(i) +
               ") is out of range: only " + std::to_string(out.positions.size()) + " vertices");
      if (mode == kModeTriangles && indices.size() % 3 != 0)
        warn(what + " has " + std::to_string(indices.size()) +
             " indices, not a multiple of 3; the last partial triangle is dropped");
      out.indices = toTriangleList(mode, indices);
      out.baseColor = materialColor(primitive.material, what);
      out.blend = isBlend(primitive.material);
      cached->push_back(std::move(out));
    }
    return *cached;
  }

  void addMeshInstance(int meshIndex, const glm::dmat4& world) {
    const glm::dmat3 linear(world);
    const double det = glm::determinant(linear);
    const bool mirrored = det < 0.0;
    // Normals go through the inverse transpose; a singular transform has none, so its
    // (flattened) instance gets normals from the geometry instead.
    const bool invertible = std::isfinite(det) && std::fabs(det) > 1e-300;
    const glm::dmat3 normalMatrix = invertible ? glm::transpose(glm::inverse(linear)) : glm::dmat3(1.0);
    for (const LocalPrimitive& primitive : meshPrimitives(meshIndex)) {
      Mesh mesh;
      mesh.name = primitive.name;
      mesh.baseColor = primitive.baseColor;
      mesh.cutout = primitive.cutout;
      mesh.texture = primitive.texture;
      mesh.blend = primitive.blend;
      mesh.texcoords = primitive.texcoords;
      mesh.positions.reserve(primitive.positions.size());
      for (const glm::vec3& p : primitive.positions)
        mesh.positions.push_back(glm::vec3(world * glm::dvec4(glm::dvec3(p), 1.0)));
      mesh.indices = primitive.indices;
      if (mirrored)
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);

      bool needGeometric = primitive.normals.empty() || !invertible;
      std::vector<char> bad;
      if (!needGeometric) {
        mesh.normals.resize(primitive.normals.size());
        bad.assign(primitive.normals.size(), 0);
        for (size_t v = 0; v < primitive.normals.size(); ++v) {
          const glm::dvec3 n = normalMatrix * glm::dvec3(primitive.normals[v]);
          const double length = glm::length(n);
          if (length > 0.0 && isFinite(n) && std::isfinite(length)) {
            mesh.normals[v] = glm::vec3(n / length);
          } else {
            bad[v] = 1;  // a zero or NaN normal in the file: patched from the geometry below
            needGeometric = true;
          }
        }
      }
      if (needGeometric) {
        Mesh geometric = mesh;
        computeVertexNormals(geometric);
        if (bad.empty()) {
          mesh.normals = std::move(geometric.normals);
        } else {
          for (size_t v = 0; v < bad.size(); ++v)
            if (bad[v]) mesh.normals[v] = geometric.normals[v];
        }
      }
      scene_.meshes.push_back(std::move(mesh));
    }
  }

  // ---- cameras and lights ----------------------------------------------------------------

  void addCamera(const tinygltf::Node& node, const glm::dmat4& world) {
    if (node.camera < 0 || static_cast<size_t>(node.camera) >= model_.cameras.size())
      fail("node '" + node.name + "' camera " + std::to_string(node.camera) + " is out of range (" +
           std::to_string(model_.cameras.size()) + " cameras)");
    const tinygltf::Camera& source = model_.cameras[static_cast<size_t>(node.camera)];
    if (source.type != "perspective") {
      warn("camera '" + source.name + "' is " + source.type + ", only perspective cameras are used");
      return;
    }
    const glm::dmat3 linear(world);
    const glm::dvec3 forward = linear * glm::dvec3(0.0, 0.0, -1.0);
    const glm::dvec3 up = linear * glm::dvec3(0.0, 1.0, 0.0);
    const double yfov = source.perspective.yfov;
    if (!(glm::length(forward) > 0.0) || !(glm::length(up) > 0.0) ||
        glm::length(glm::cross(forward, up)) <= 0.0) {
      warn("camera on node '" + node.name + "' has a degenerate transform, ignored");
      return;
    }
    if (!(yfov > 0.0 && yfov < 3.14159)) {
      warn("camera on node '" + node.name + "' has yfov " + std::to_string(yfov) + ", ignored");
      return;
    }
    Camera camera;
    camera.eye = glm::vec3(world[3]);
    camera.target = glm::vec3(glm::dvec3(world[3]) + glm::normalize(forward));
    camera.up = glm::vec3(glm::normalize(up));
    camera.yfov = static_cast<float>(yfov);
    scene_.cameras.push_back(camera);
  }

  void readLight(const tinygltf::Node& node, const glm::dmat4& world) {
    if (scene_.hasLight) return;
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end() || !ext->second.IsObject() || !ext->second.Has("light")) return;
    const tinygltf::Value& index = ext->second.Get("light");
    if (!index.IsNumber()) return;
    const int lightIndex = index.GetNumberAsInt();
    if (lightIndex < 0 || static_cast<size_t>(lightIndex) >= model_.lights.size())
      fail("node '" + node.name + "' light " + std::to_string(lightIndex) + " is out of range (" +
           std::to_string(model_.lights.size()) + " lights)");
    const tinygltf::Light& light = model_.lights[static_cast<size_t>(lightIndex)];
    if (light.type != "directional") return;
    const glm::dvec3 direction = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
    const double length = glm::length(direction);
    if (!(length > 0.0) || !std::isfinite(length)) {
      warn("light on node '" + node.name + "' has a degenerate transform, ignored");
      return;
    }
    glm::dvec3 color(1.0);
    if (light.color.size() == 3) color = glm::dvec3(light.color[0], light.color[1], light.color[2]);
    color *= light.intensity;
    if (!isFinite(color)) color = glm::dvec3(1.0);
    color = glm::max(color, glm::dvec3(0.0));
    const double peak = std::max({color.x, color.y, color.z});
    if (peak > kMaxLightScale) {
      warn("light '" + light.name + "' intensity scaled down to " + std::to_string(kMaxLightScale));
      color *= kMaxLightScale / peak;
    }
    scene_.light.direction = glm::vec3(direction / length);
    scene_.light.color = glm::vec3(color);
    scene_.hasLight = true;
  }

  const std::string& path_;
  const tinygltf::Model& model_;
  const ImageRequests& images_;  // decoded alpha of the images MASK materials read
  const bool quiet_;
  const bool skipBlend_;  // --blend-materials skip
  size_t skippedBlend_ = 0;  // primitives dropped for it
  std::map<int, MaterialCutout> cutouts_;  // per material
  std::map<int, int> textures_;            // per material: its Scene::textures index, or -1
  std::map<int, int> textureIndex_;        // per glTF texture: its Scene::textures index
  size_t invisiblePrimitives_ = 0;         // alpha MASK under the cutoff everywhere: not drawn
  Scene scene_;
  std::vector<std::optional<std::vector<LocalPrimitive>>> meshCache_;
  std::vector<char> onStack_;
  mutable std::map<int, std::vector<unsigned char>> decoded_;  // EXT_meshopt_compression views
  size_t skinned_ = 0;
  size_t morphed_ = 0;
};

// The credit line from ATTRIBUTION.txt beside the file: the text after the first label that
// ends in "credit:" (else one that is exactly "attribution:"). A quoted credit runs to its
// closing quote; an unquoted one to the next blank line. Quotes are stripped.
std::string readCredit(const fs::path& file) {
  std::ifstream in(file.parent_path() / "ATTRIBUTION.txt");
  if (!in) return {};
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line) && lines.size() < 10000;) lines.push_back(line);

  auto findLabel = [&](auto matches) -> std::optional<std::pair<size_t, std::string>> {
    for (size_t i = 0; i < lines.size(); ++i) {
      const std::string line = trim(lines[i]);
      const size_t colon = line.find(':');
      if (colon == std::string::npos) continue;
      if (matches(lower(trim(line.substr(0, colon))))) return std::make_pair(i, trim(line.substr(colon + 1)));
    }
    return std::nullopt;
  };
  auto found = findLabel([](const std::string& label) {
    return label.size() >= 6 && label.compare(label.size() - 6, 6, "credit") == 0;
  });
  if (!found) found = findLabel([](const std::string& label) { return label == "attribution"; });
  if (!found) return {};

  std::string credit = found->second;
  const bool quoted = !credit.empty() && credit.front() == '"';
  auto complete = [&] {
    return quoted ? std::count(credit.begin(), credit.end(), '"') >= 2 : false;
  };
  for (size_t i = found->first + 1, n = 1; i < lines.size() && n < kMaxCreditLines && !complete(); ++i, ++n) {
    const std::string next = trim(lines[i]);
    if (next.empty()) break;
    credit += (credit.empty() ? "" : " ") + next;
  }
  if (quoted) {
    const size_t close = credit.find('"', 1);
    credit = credit.substr(1, close == std::string::npos ? std::string::npos : close - 1);
  }
  return trim(credit);
}

}  // namespace

namespace {

// tinygltf's file callbacks for in-memory parsing without a folder: every external buffer
// is refused, so fuzzed bytes can never make the loader read a file of the machine.
// (FileExists says yes so that tinygltf goes on to the read, which fails with the reason.)
bool noFileExists(const std::string&, void*) { return true; }
std::string noExpand(const std::string& path, void*) { return path; }
bool noReadWholeFile(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
  if (err) *err += "external file \"" + path + "\" not allowed here\n";
  return false;
}
bool noWriteWholeFile(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

// A buffer URI percent-decoded, as tinygltf decodes it before it looks for the file.
std::string decodeUri(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

bool isMeshoptFallback(const nlohmann::json& buffer) {
  const auto extensions = buffer.find("extensions");
  if (extensions == buffer.end() || !extensions->is_object()) return false;
  const auto meshopt = extensions->find("EXT_meshopt_compression");
  if (meshopt == extensions->end() || !meshopt->is_object()) return false;
  const auto fallback = meshopt->find("fallback");
  return fallback != meshopt->end() && fallback->is_boolean() && fallback->get<bool>();
}

// The image a material's base-colour texture reads (the texture's source, or its
// EXT_texture_webp source), or -1.
int baseColorImage(const nlohmann::json& material, const nlohmann::json& textures) {
  if (!material.is_object()) return -1;
  const nlohmann::json* info = nullptr;
  const auto pbr = material.find("pbrMetallicRoughness");
  if (pbr != material.end() && pbr->is_object() && pbr->contains("baseColorTexture")) info = &(*pbr)["baseColorTexture"];
  if (!info || !info->is_object() || !info->contains("index") || !(*info)["index"].is_number_unsigned()) return -1;
  const size_t t = (*info)["index"].get<size_t>();
  if (t >= textures.size() || !textures[t].is_object()) return -1;
  const nlohmann::json& texture = textures[t];
  if (texture.contains("source") && texture["source"].is_number_unsigned())
    return static_cast<int>(std::min<size_t>(texture["source"].get<size_t>(), INT32_MAX));
  const nlohmann::json* webp = nullptr;
  if (texture.contains("extensions") && texture["extensions"].is_object() &&
      texture["extensions"].contains("EXT_texture_webp"))
    webp = &texture["extensions"]["EXT_texture_webp"];
  if (webp && webp->is_object() && webp->contains("source") && (*webp)["source"].is_number_unsigned())
    return static_cast<int>(std::min<size_t>((*webp)["source"].get<size_t>(), INT32_MAX));
  return -1;
}

// The images mrr decodes, from the JSON before tinygltf parses it: `alpha`, those alpha-MASK
// materials' base colours read (their cutouts); `colour`, those the base colours of the
// materials some primitive draws read (their albedo; BLEND ones not with `skipBlend`). No
// other image (normal, occlusion, emissive maps, unused materials') is decoded.
void wantedImages(const nlohmann::json& doc, bool skipBlend, std::set<int>& alpha, std::set<int>& colour) {
  const auto materials = doc.find("materials"), textures = doc.find("textures");
  if (materials == doc.end() || !materials->is_array() || textures == doc.end() || !textures->is_array()) return;
  std::set<size_t> drawn;  // materials some primitive uses
  const auto meshes = doc.find("meshes");
  if (meshes != doc.end() && meshes->is_array())
    for (const nlohmann::json& mesh : *meshes) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (const nlohmann::json& primitive : mesh["primitives"])
        if (primitive.is_object() && primitive.contains("material") && primitive["material"].is_number_unsigned())
          drawn.insert(primitive["material"].get<size_t>());
    }
  for (size_t m = 0; m < materials->size(); ++m) {
    const nlohmann::json& material = (*materials)[m];
    const int image = baseColorImage(material, *textures);
    if (image < 0) continue;
    const std::string mode = material.value("alphaMode", std::string());
    if (mode == "MASK") alpha.insert(image);
    if (drawn.count(m) && !(skipBlend && mode == "BLEND")) colour.insert(image);
  }
}

// What mrr settles in the JSON before tinygltf parses it, since tinygltf 2.7.0 reads every
// buffer and image first and reports what goes wrong there in its own words:
// - a required extension mrr cannot honour is refused by name, before any buffer is read;
// - an absent external buffer is named with the path where it was expected;
// - EXT_meshopt_compression fallback buffers (no uri and no data, which tinygltf refuses)
//   become a one-byte placeholder: their data is only ever the compressed views' output;
// - KHR_draco_mesh_compression primitives lose `indices` (an accessor without a bufferView,
//   which tinygltf refuses): the triangles come with the Draco mesh;
// - images are replaced by placeholders but for the base-colour images of alpha-MASK materials
//   and of the materials drawn (wantedImages), so no other texture is read or decoded and
//   absent ones warn of nothing.
// Returns the bytes to parse: the same when nothing changed, else the JSON (or the GLB)
// rewritten. Bytes whose JSON does not parse go to tinygltf unchanged, for it to report.
std::vector<unsigned char> prepareJson(const std::vector<unsigned char>& bytes, const std::string& name,
                                       const std::string& baseDir, bool binary, bool skipBlend,
                                       std::set<int>* wanted, std::set<int>* wantedColor) {
  using nlohmann::json;
  size_t jsonBegin = 0, jsonSize = bytes.size(), glbLength = 0;
  if (binary) {
    // The GLB header as tinygltf checks it (little-endian, like every machine mrr runs on).
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) return bytes;
    uint32_t length = 0, chunkLength = 0, chunkType = 0;
    std::memcpy(&length, bytes.data() + 8, 4);
    std::memcpy(&chunkLength, bytes.data() + 12, 4);
    std::memcpy(&chunkType, bytes.data() + 16, 4);
    const uint64_t jsonEnd = 20ull + chunkLength;
    if (length > bytes.size() || chunkType != 0x4E4F534Au || chunkLength < 1 || jsonEnd > length || jsonEnd % 4 != 0)
      return bytes;
    jsonBegin = 20;
    jsonSize = chunkLength;
    glbLength = length;
  }
  const auto begin = bytes.begin() + static_cast<std::ptrdiff_t>(jsonBegin);
  json doc = json::parse(begin, begin + static_cast<std::ptrdiff_t>(jsonSize), nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return bytes;

  const auto required = doc.find("extensionsRequired");
  if (required != doc.end() && required->is_array())
    for (const json& ext : *required)
      if (ext.is_string() && !readableExtension(ext.get<std::string>()))
        throw MrrError(name + ": " + unreadableExtension(ext.get<std::string>()));

  bool changed = false;
  const auto buffers = doc.find("buffers");
  if (buffers != doc.end() && buffers->is_array()) {
    for (size_t i = 0; i < buffers->size(); ++i) {
      json& buffer = (*buffers)[i];
      if (!buffer.is_object()) continue;
      const auto uri = buffer.find("uri");
      if (isMeshoptFallback(buffer)) {
        buffer = {{"byteLength", 1},
                  {"uri", "data:application/octet-stream;base64,AA=="},
                  {"extensions", buffer["extensions"]}};
        changed = true;
      } else if (uri != buffer.end() && uri->is_string() && !baseDir.empty() &&
                 uri->get<std::string>().rfind("data:", 0) != 0) {
        const std::string file = uri->get<std::string>();
        std::error_code ec;
        const fs::path expected = fs::absolute(fs::path(baseDir) / decodeUri(file), ec).lexically_normal();
        if (!ec && !fs::exists(expected, ec))
          throw MrrError(name + ": buffer " + std::to_string(i) + ": file " + file + " not found (expected at " +
                         expected.string() + ")");
      } else if (uri == buffer.end() && !binary) {
        throw MrrError(name + ": buffer " + std::to_string(i) +
                       " has no uri (only a .glb's own binary chunk may leave it out)");
      }
    }
  }
  const auto meshes = doc.find("meshes");
  if (meshes != doc.end() && meshes->is_array())
    for (json& mesh : *meshes) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (json& primitive : mesh["primitives"]) {
        if (!primitive.is_object() || !primitive.contains("indices")) continue;
        const auto extensions = primitive.find("extensions");
        if (extensions != primitive.end() && extensions->is_object() &&
            extensions->contains("KHR_draco_mesh_compression")) {
          primitive.erase("indices");
          changed = true;
        }
      }
    }
  // Images: only base-colour images are read (wantedImages); every other one becomes a
  // one-byte placeholder that is never decoded, so indices hold.
  std::set<int> alpha, colour;
  wantedImages(doc, skipBlend, alpha, colour);
  if (wanted) *wanted = alpha;
  if (wantedColor) *wantedColor = colour;
  const auto images = doc.find("images");
  if (images != doc.end() && images->is_array()) {
    for (size_t i = 0; i < images->size(); ++i) {
      if (alpha.count(static_cast<int>(i)) || colour.count(static_cast<int>(i))) continue;
      (*images)[i] = {{"uri", "data:image/png;base64,AA=="}};
      changed = true;
    }
  } else if (doc.erase("images") > 0) {
    changed = true;
  }
  if (!changed) return bytes;

  std::string text = doc.dump(-1, ' ', false, json::error_handler_t::replace);
  if (!binary) return {text.begin(), text.end()};
  while (text.size() % 4 != 0) text += ' ';  // chunks stay 4-byte aligned
  const size_t rest = glbLength - (jsonBegin + jsonSize);
  const uint64_t total = 20ull + text.size() + rest;
  if (total > UINT32_MAX) return bytes;
  std::vector<unsigned char> out(bytes.begin(), bytes.begin() + 20);
  const auto total32 = static_cast<uint32_t>(total), jsonLength = static_cast<uint32_t>(text.size());
  std::memcpy(out.data() + 8, &total32, 4);
  std::memcpy(out.data() + 12, &jsonLength, 4);
  out.insert(out.end(), text.begin(), text.end());
  const auto restBegin = bytes.begin() + static_cast<std::ptrdiff_t>(jsonBegin + jsonSize);
  out.insert(out.end(), restBegin, restBegin + static_cast<std::ptrdiff_t>(rest));
  return out;
}

// The one path from bytes to a validated scene: tinygltf, then mrr's Loader and checks.
Scene parseGltf(const std::vector<unsigned char>& bytes, const std::string& name, const std::string& baseDir,
                bool binary, const LoadOptions& options) {
  require(!bytes.empty(), name + ": empty file, not a valid glTF file");
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  std::vector<unsigned char> prepared;
  ImageRequests images;
  try {
    prepared = prepareJson(bytes, name, baseDir, binary, options.skipBlend, &images.wanted, &images.wantedColor);
  } catch (const MrrError&) {
    throw;
  } catch (const std::exception& e) {
    throw MrrError(name + ": not a valid glTF file: " + oneLine(e.what()));
  }
  try {
    tinygltf::TinyGLTF gltf;
    gltf.SetImageLoader(decodeWantedImage, &images);
    if (baseDir.empty())
      gltf.SetFsCallbacks({noFileExists, noExpand, noReadWholeFile, noWriteWholeFile, nullptr});
    const auto size = static_cast<unsigned int>(std::min<size_t>(prepared.size(), 0xffffffffu));
    ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, &warn, prepared.data(), size, baseDir)
                : gltf.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(prepared.data()),
                                           size, baseDir);
  } catch (const std::exception& e) {
    throw MrrError(name + ": not a valid glTF file: " + oneLine(e.what()));
  }
  if (!ok) {
    const std::string reason = oneLine(err);
    throw MrrError(name + ": not a valid glTF file: " + (reason.empty() ? "tinygltf failed" : reason));
  }
  if (!oneLine(warn).empty() && !options.quiet) std::cerr << "mrr: warning: " << name << ": " << oneLine(warn) << "\n";

  Scene scene;
  try {
    scene = Loader(name, model, images, options.quiet, options.skipBlend).build();
  } catch (const MrrError&) {
    throw;
  } catch (const std::exception& e) {
    // bad_alloc from an absurd but in-bounds count, or anything else unexpected.
    throw MrrError(name + ": cannot load: " + oneLine(e.what()));
  }
  if (options.flipUp) flipUp(scene);
  validateScene(scene, name);
  return scene;
}

}  // namespace

Scene loadGltf(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  require(fs::exists(status), path + ": no such file");
  require(!fs::is_directory(status), path + ": is a directory, expected a .gltf or .glb file");
  require(fs::is_regular_file(status), path + ": not a regular file");
  const std::string extension = lower(fs::path(path).extension().string());
  require(extension == ".gltf" || extension == ".glb",
          path + ": unsupported extension '" + fs::path(path).extension().string() +
              "', expected .gltf or .glb");
  const auto size = fs::file_size(path, ec);
  require(!ec, path + ": cannot read the file size (" + ec.message() + ")");
  require(size > 0, path + ": empty file, not a valid glTF file");
  require(size <= kMaxFileBytes, path + ": " + std::to_string(size) + " bytes, over the limit of " +
                                     std::to_string(kMaxFileBytes) + " for one glTF file");

  std::vector<unsigned char> bytes(static_cast<size_t>(size));
  {
    std::ifstream in(path, std::ios::binary);
    require(in.good(), path + ": cannot open for reading");
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    require(in.gcount() == static_cast<std::streamsize>(bytes.size()), path + ": cannot read the whole file");
  }
  std::string baseDir = fs::path(path).parent_path().string();
  if (baseDir.empty()) baseDir = ".";
  Scene scene = parseGltf(bytes, path, baseDir, extension == ".glb", options);
  scene.credit = readCredit(fs::path(path));
  return scene;
}

Scene loadGltfFromMemory(const std::vector<unsigned char>& bytes, const std::string& name, bool binary,
                         const LoadOptions& options) {
  return parseGltf(bytes, name, "", binary, options);
}

}  // namespace mrr
