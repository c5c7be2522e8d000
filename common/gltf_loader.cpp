#include "common/gltf_loader.h"

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
#include <optional>
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

// Textures are ignored (one albedo per mesh), so images are never decoded.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
               const unsigned char*, int, void*) {
  return true;
}

// One primitive, read once per glTF mesh in the mesh's own space, then instanced per node.
struct LocalPrimitive {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;  // empty: compute after transforming
  std::vector<uint32_t> indices;   // triangle list
  glm::vec3 baseColor{1.0f};
};

class Loader {
 public:
  Loader(const std::string& path, const tinygltf::Model& model, bool quiet)
      : path_(path), model_(model), quiet_(quiet) {}

  Scene build() {
    checkRequiredExtensions();
    meshCache_.resize(model_.meshes.size());
    onStack_.assign(model_.nodes.size(), 0);
    for (int root : rootNodes()) visit(root, glm::dmat4(1.0), 0);
    scene_.name = path_;
    return std::move(scene_);
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    throw MrrError(path_ + ": " + message);
  }

  void warn(const std::string& message) const {
    if (!quiet_) std::cerr << "mrr: warning: " << path_ << ": " << message << "\n";
  }

  void checkRequiredExtensions() const {
    // Extensions that only change what we ignore anyway (textures, extra material
    // properties) or that we read (lights) are fine; anything else changes the geometry.
    for (const std::string& ext : model_.extensionsRequired) {
      const bool harmless = ext == "KHR_lights_punctual" || ext.rfind("KHR_materials_", 0) == 0 ||
                            ext.rfind("KHR_texture_", 0) == 0 || ext == "EXT_texture_webp" ||
                            ext == "KHR_mesh_quantization";
      if (!harmless) fail("requires the unsupported glTF extension " + ext);
    }
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
    else if (node.mesh < -1) fail("node " + std::to_string(index) + " mesh index " + std::to_string(node.mesh) + " is invalid");
    if (node.camera != -1) addCamera(node, world);
    readLight(node, world);
    for (int child : node.children) visit(child, world, depth + 1);
    onStack_[i] = 0;
  }

  // ---- accessors -------------------------------------------------------------------------

  struct AccessorView {
    const unsigned char* data = nullptr;  // first element
    size_t stride = 0;
    size_t count = 0;
    int componentType = 0;
  };

  // Resolves accessor -> bufferView -> buffer with every range checked, so that reading
  // `count` elements of `stride` bytes from `data` stays inside the buffer.
  AccessorView view(int accessorIndex, const std::string& what) const {
    if (accessorIndex < 0 || static_cast<size_t>(accessorIndex) >= model_.accessors.size())
      fail(what + " accessor " + std::to_string(accessorIndex) + " is out of range (" +
           std::to_string(model_.accessors.size()) + " accessors)");
    const tinygltf::Accessor& accessor = model_.accessors[static_cast<size_t>(accessorIndex)];
    const std::string where = what + " (accessor " + std::to_string(accessorIndex) + ")";
    if (accessor.sparse.isSparse) fail(where + " is sparse; sparse accessors are not supported");
    if (accessor.bufferView < 0 || static_cast<size_t>(accessor.bufferView) >= model_.bufferViews.size())
      fail(where + " has no valid bufferView (" + std::to_string(accessor.bufferView) + ")");
    const tinygltf::BufferView& bufferView = model_.bufferViews[static_cast<size_t>(accessor.bufferView)];
    if (bufferView.buffer < 0 || static_cast<size_t>(bufferView.buffer) >= model_.buffers.size())
      fail(where + " bufferView " + std::to_string(accessor.bufferView) + " names buffer " +
           std::to_string(bufferView.buffer) + ", which does not exist");
    const tinygltf::Buffer& buffer = model_.buffers[static_cast<size_t>(bufferView.buffer)];

    const size_t elementSize = componentSize(accessor.componentType) * componentCount(accessor.type);
    if (elementSize == 0) fail(where + " has an invalid componentType or type");
    const size_t stride = bufferView.byteStride != 0 ? bufferView.byteStride : elementSize;
    if (stride < elementSize)
      fail(where + " byteStride " + std::to_string(stride) + " is smaller than its element size " +
           std::to_string(elementSize));
    const size_t bufferSize = buffer.data.size();
    if (bufferView.byteOffset > bufferSize || bufferView.byteLength > bufferSize - bufferView.byteOffset)
      fail(where + " bufferView " + std::to_string(accessor.bufferView) + " (offset " +
           std::to_string(bufferView.byteOffset) + ", length " + std::to_string(bufferView.byteLength) +
           ") runs past the end of buffer " + std::to_string(bufferView.buffer) + " (" +
           std::to_string(bufferSize) + " bytes)");
    AccessorView result;
    result.stride = stride;
    result.count = accessor.count;
    result.componentType = accessor.componentType;
    if (accessor.count == 0) return result;
    // Bytes needed: byteOffset + stride·(count−1) + elementSize, computed without overflow.
    const size_t available = bufferView.byteLength;
    const bool fits = accessor.byteOffset <= available &&
                      elementSize <= available - accessor.byteOffset &&
                      accessor.count - 1 <= (available - accessor.byteOffset - elementSize) / stride;
    if (!fits)
      fail(where + " needs " + std::to_string(accessor.count) + " elements of " +
           std::to_string(elementSize) + " bytes from offset " + std::to_string(accessor.byteOffset) +
           " but its bufferView holds only " + std::to_string(available) + " bytes");
    result.data = buffer.data.data() + bufferView.byteOffset + accessor.byteOffset;
    return result;
  }

  // Non-finite positions are an error; non-finite normals (exporters write NaN for the normal
  // of a degenerate face) are allowed here and repaired from the geometry later.
  std::vector<glm::vec3> readVec3(int accessorIndex, const std::string& what, bool allowNonFinite = false) const {
    const tinygltf::Accessor* accessor =
        (accessorIndex >= 0 && static_cast<size_t>(accessorIndex) < model_.accessors.size())
            ? &model_.accessors[static_cast<size_t>(accessorIndex)]
            : nullptr;
    if (accessor && (accessor->componentType != TINYGLTF_COMPONENT_TYPE_FLOAT ||
                     accessor->type != TINYGLTF_TYPE_VEC3))
      fail(what + " (accessor " + std::to_string(accessorIndex) + ") must be FLOAT VEC3, not " +
           componentName(accessor->componentType) + " " + typeName(accessor->type));
    const AccessorView v = view(accessorIndex, what);
    std::vector<glm::vec3> out(v.count);
    for (size_t i = 0; i < v.count; ++i) {
      float xyz[3];
      std::memcpy(xyz, v.data + i * v.stride, sizeof xyz);  // no alignment assumptions
      out[i] = glm::vec3(xyz[0], xyz[1], xyz[2]);
      if (!allowNonFinite && (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])))
        fail(what + " element " + std::to_string(i) + " is not finite (" + std::to_string(xyz[0]) +
             ", " + std::to_string(xyz[1]) + ", " + std::to_string(xyz[2]) + ")");
    }
    return out;
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
    const AccessorView v = view(accessorIndex, what);
    std::vector<uint32_t> out(v.count);
    for (size_t i = 0; i < v.count; ++i) {
      const unsigned char* p = v.data + i * v.stride;
      if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
        out[i] = p[0];
      } else if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        uint16_t value;
        std::memcpy(&value, p, sizeof value);
        out[i] = value;
      } else {
        std::memcpy(&out[i], p, sizeof(uint32_t));
      }
    }
    return out;
  }

  // ---- meshes ----------------------------------------------------------------------------

  glm::vec3 materialColor(int material, const std::string& what) const {
    if (material == -1) return glm::vec3(1.0f);
    if (material < 0 || static_cast<size_t>(material) >= model_.materials.size())
      fail(what + " material " + std::to_string(material) + " is out of range (" +
           std::to_string(model_.materials.size()) + " materials)");
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
      const auto position = primitive.attributes.find("POSITION");
      if (position == primitive.attributes.end()) fail(what + " has no POSITION attribute");

      LocalPrimitive out;
      out.name = meshName + "/" + std::to_string(k);
      out.positions = readVec3(position->second, what + " POSITION");
      const auto normal = primitive.attributes.find("NORMAL");
      if (normal != primitive.attributes.end()) {
        out.normals = readVec3(normal->second, what + " NORMAL", true);
        if (out.normals.size() != out.positions.size())
          fail(what + " has " + std::to_string(out.normals.size()) + " normals for " +
               std::to_string(out.positions.size()) + " positions");
        const auto broken = std::count_if(out.normals.begin(), out.normals.end(), [](const glm::vec3& n) {
          return !isFinite(glm::dvec3(n)) || !(glm::length(n) > 0.0f);
        });
        if (broken > 0)
          warn(what + " has " + std::to_string(broken) + " zero or non-finite normals, replaced by computed ones");
      }
      std::vector<uint32_t> indices;
      if (primitive.indices >= 0) {
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
  const bool quiet_;
  Scene scene_;
  std::vector<std::optional<std::vector<LocalPrimitive>>> meshCache_;
  std::vector<char> onStack_;
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

// The one path from bytes to a validated scene: tinygltf, then mrr's Loader and checks.
Scene parseGltf(const std::vector<unsigned char>& bytes, const std::string& name, const std::string& baseDir,
                bool binary, const LoadOptions& options) {
  require(!bytes.empty(), name + ": empty file, not a valid glTF file");
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  try {
    tinygltf::TinyGLTF gltf;
    gltf.SetImageLoader(skipImage, nullptr);
    if (baseDir.empty())
      gltf.SetFsCallbacks({noFileExists, noExpand, noReadWholeFile, noWriteWholeFile, nullptr});
    const auto size = static_cast<unsigned int>(std::min<size_t>(bytes.size(), 0xffffffffu));
    ok = binary ? gltf.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), size, baseDir)
                : gltf.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(bytes.data()), size,
                                           baseDir);
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
    scene = Loader(name, model, options.quiet).build();
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
