#pragma once
// The glTF documents the loader's tests write at test time: GltfBuilder assembles the JSON
// and one binary buffer (.gltf with a base64 data URI, or a .glb), plus the checks the
// loader tests share. Header-only, shared by gltf_test.cpp and gltf_compressed_test.cpp.
#include <gtest/gtest.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "scenes/gltf_loader.h"
#include "tests/test_support.h"

namespace mrr::gltftest {

using nlohmann::json;
namespace fs = std::filesystem;
using mrr::test::base64;

inline constexpr int kFloat = 5126;
inline constexpr int kUnsignedByte = 5121;
inline constexpr int kUnsignedShort = 5123;
inline constexpr int kUnsignedInt = 5125;

inline void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// Builds a glTF document and its one binary buffer.
class GltfBuilder {
 public:
  json doc = {{"asset", {{"version", "2.0"}}}};
  std::vector<uint8_t> bin;

  int push(const std::string& key, const json& value) {
    doc[key].push_back(value);
    return static_cast<int>(doc[key].size()) - 1;
  }

  // Appends bytes (4-byte aligned) as a new bufferView; returns its index.
  int addView(const void* data, size_t bytes, size_t stride = 0) {
    while (bin.size() % 4 != 0) bin.push_back(0);
    const size_t offset = bin.size();
    const auto* p = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), p, p + bytes);
    json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    if (stride != 0) view["byteStride"] = stride;
    return push("bufferViews", view);
  }

  int addAccessor(int view, int componentType, const std::string& type, size_t count, size_t byteOffset = 0) {
    json accessor = {{"bufferView", view}, {"componentType", componentType}, {"type", type}, {"count", count}};
    if (byteOffset != 0) accessor["byteOffset"] = byteOffset;
    return push("accessors", accessor);
  }

  int addVec3(const std::vector<glm::vec3>& values) {
    return addAccessor(addView(values.data(), values.size() * sizeof(glm::vec3)), kFloat, "VEC3", values.size());
  }

  int addIndices(const std::vector<uint32_t>& indices, int componentType = kUnsignedInt) {
    std::vector<uint8_t> bytes;
    for (uint32_t index : indices) {
      const size_t size = componentType == kUnsignedByte ? 1 : componentType == kUnsignedShort ? 2 : 4;
      for (size_t b = 0; b < size; ++b) bytes.push_back(static_cast<uint8_t>((index >> (8 * b)) & 0xFFu));
    }
    return addAccessor(addView(bytes.data(), bytes.size()), componentType, "SCALAR", indices.size());
  }

  // A primitive from positions, optional normals and optional indices.
  json primitive(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                 const std::vector<uint32_t>& indices, int material = -1, int mode = -1) {
    json p = {{"attributes", {{"POSITION", addVec3(positions)}}}};
    if (!normals.empty()) p["attributes"]["NORMAL"] = addVec3(normals);
    if (!indices.empty()) p["indices"] = addIndices(indices);
    if (material >= 0) p["material"] = material;
    if (mode >= 0) p["mode"] = mode;
    return p;
  }

  int addMesh(const std::string& name, const std::vector<json>& primitives) {
    return push("meshes", {{"name", name}, {"primitives", primitives}});
  }

  int addMaterial(const std::vector<double>& baseColor) {
    return push("materials", {{"pbrMetallicRoughness", {{"baseColorFactor", baseColor}}}});
  }

  int addNode(const json& node) { return push("nodes", node); }

  void setRoots(const std::vector<int>& roots) {
    doc["scenes"] = json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  json finished(bool glb) const {
    json d = doc;
    if (!bin.empty()) {
      json buffer = {{"byteLength", bin.size()}};
      if (!glb) buffer["uri"] = "data:application/octet-stream;base64," + base64(bin);
      d["buffers"] = json::array({buffer});
    }
    return d;
  }

  std::string writeGltf(const std::string& dir, const std::string& name) const {
    const std::string path = (fs::path(dir) / name).string();
    writeFile(path, finished(false).dump(1));
    return path;
  }

  std::string glbBytes() const { return test::glbFile(finished(true).dump(), bin); }

  std::string writeGlb(const std::string& dir, const std::string& name) const {
    const std::string path = (fs::path(dir) / name).string();
    writeFile(path, glbBytes());
    return path;
  }
};

inline const std::vector<glm::vec3> kTriangle = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};  // CCW seen from +Z
inline const std::vector<glm::vec3> kUpNormals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};

// A one-triangle scene; `node` gets "mesh": 0 added.
inline GltfBuilder singleTriangle(json node = json::object()) {
  GltfBuilder b;
  b.addMesh("tri", {b.primitive(kTriangle, kUpNormals, {0, 1, 2})});
  node["mesh"] = 0;
  b.setRoots({b.addNode(node)});
  return b;
}

inline void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = 1e-5f) {
  EXPECT_LE(glm::distance(actual, expected), tolerance)
      << "actual (" << actual.x << ", " << actual.y << ", " << actual.z << ") expected (" << expected.x
      << ", " << expected.y << ", " << expected.z << ")";
}

// Loading `path` must throw MrrError with one line naming the file (and `fragment`, if given).
inline void expectLoadError(const std::string& path, const std::string& fragment = "") {
  try {
    loadGltf(path);
    ADD_FAILURE() << "no error for " << path;
  } catch (const MrrError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    if (!fragment.empty()) {
      EXPECT_NE(message.find(fragment), std::string::npos) << message;
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an MrrError: " << e.what();
  }
}

}  // namespace mrr::gltftest
