#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/paths.h"

namespace fs = std::filesystem;

namespace mrr::test {

std::string scratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "misc";
  for (char& c : name)
    if (c == '/') c = '_';
  fs::path dir = fs::path(MRR_TEST_TMP) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string sharedScene(const std::string& relative) {
  return (fs::path(sharedScenesDir()) / relative).string();
}

bool haveSharedScene(const std::string& relative) { return fs::exists(sharedScene(relative)); }

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b0 = bytes[i];
    const uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0u;
    const uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0u;
    const uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

std::string glbFile(const std::string& json, const std::vector<uint8_t>& bin) {
  auto appendU32 = [](std::string& out, uint32_t value) {
    for (int i = 0; i < 4; ++i) out += static_cast<char>((value >> (8 * i)) & 0xFFu);
  };
  std::string text = json;
  while (text.size() % 4 != 0) text += ' ';
  std::string data(bin.begin(), bin.end());
  while (data.size() % 4 != 0) data += '\0';
  std::string out;
  appendU32(out, 0x46546C67u);  // "glTF"
  appendU32(out, 2);
  appendU32(out, static_cast<uint32_t>(12 + 8 + text.size() + (data.empty() ? 0 : 8 + data.size())));
  appendU32(out, static_cast<uint32_t>(text.size()));
  appendU32(out, 0x4E4F534Au);  // "JSON"
  out += text;
  if (!data.empty()) {
    appendU32(out, static_cast<uint32_t>(data.size()));
    appendU32(out, 0x004E4942u);  // "BIN\0"
    out += data;
  }
  return out;
}

namespace {

// Appends `count` elements of `values` to the buffer and returns the new accessor's index.
template <typename T>
int addAccessor(tinygltf::Model& model, const T* values, size_t count, int type, int componentType, int target) {
  std::vector<unsigned char>& data = model.buffers[0].data;
  while (data.size() % 4 != 0) data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = data.size();
  view.byteLength = count * sizeof(T);
  view.target = target;
  data.resize(data.size() + view.byteLength);
  std::memcpy(data.data() + view.byteOffset, values, view.byteLength);
  model.bufferViews.push_back(view);
  tinygltf::Accessor accessor;
  accessor.bufferView = static_cast<int>(model.bufferViews.size()) - 1;
  accessor.componentType = componentType;
  accessor.type = type;
  accessor.count = count;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

std::vector<double> toDoubles(const glm::mat4& m) {
  std::vector<double> out(16);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[static_cast<size_t>(4 * c + r)] = m[c][r];
  return out;
}

}  // namespace

std::vector<unsigned char> sceneToGltf(const Scene& scene, bool binary) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "mrr tests";
  model.buffers.emplace_back();
  model.scenes.emplace_back();
  model.defaultScene = 0;
  auto addNode = [&](tinygltf::Node node) {
    model.nodes.push_back(std::move(node));
    model.scenes[0].nodes.push_back(static_cast<int>(model.nodes.size()) - 1);
  };
  for (const Mesh& mesh : scene.meshes) {
    tinygltf::Primitive primitive;
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    const int positions = addAccessor(model, mesh.positions.data(), mesh.positions.size(), TINYGLTF_TYPE_VEC3,
                                      TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    model.accessors[static_cast<size_t>(positions)].minValues = {lo.x, lo.y, lo.z};
    model.accessors[static_cast<size_t>(positions)].maxValues = {hi.x, hi.y, hi.z};
    primitive.attributes["POSITION"] = positions;
    primitive.attributes["NORMAL"] = addAccessor(model, mesh.normals.data(), mesh.normals.size(), TINYGLTF_TYPE_VEC3,
                                                 TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.indices = addAccessor(model, mesh.indices.data(), mesh.indices.size(), TINYGLTF_TYPE_SCALAR,
                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    tinygltf::Material material;
    material.pbrMetallicRoughness.baseColorFactor = {mesh.baseColor.x, mesh.baseColor.y, mesh.baseColor.z, 1.0};
    model.materials.push_back(material);
    primitive.material = static_cast<int>(model.materials.size()) - 1;
    tinygltf::Mesh gltfMesh;
    gltfMesh.name = mesh.name;
    gltfMesh.primitives.push_back(primitive);
    model.meshes.push_back(gltfMesh);
    tinygltf::Node node;
    node.name = mesh.name;
    node.mesh = static_cast<int>(model.meshes.size()) - 1;
    addNode(node);
  }
  for (const Camera& camera : scene.cameras) {
    tinygltf::Camera gltfCamera;
    gltfCamera.type = "perspective";
    gltfCamera.perspective.yfov = camera.yfov;
    gltfCamera.perspective.aspectRatio = 16.0 / 9.0;
    gltfCamera.perspective.znear = 0.01;
    model.cameras.push_back(gltfCamera);
    tinygltf::Node node;
    node.camera = static_cast<int>(model.cameras.size()) - 1;
    node.matrix = toDoubles(glm::inverse(glm::lookAt(camera.eye, camera.target, camera.up)));
    addNode(node);
  }
  {
    // glTF lights shine down their node's -Z; colour in [0, 1], the magnitude in intensity.
    const float peak = std::max({scene.light.color.x, scene.light.color.y, scene.light.color.z, 1e-6f});
    tinygltf::Light light;
    light.type = "directional";
    light.color = {scene.light.color.x / peak, scene.light.color.y / peak, scene.light.color.z / peak};
    light.intensity = peak;
    model.lights.push_back(light);
    model.extensionsUsed.push_back("KHR_lights_punctual");
    const glm::quat rotation(glm::vec3(0, 0, -1), glm::normalize(scene.light.direction));
    tinygltf::Node node;
    node.rotation = {rotation.x, rotation.y, rotation.z, rotation.w};
    tinygltf::Value::Object ext;
    ext["light"] = tinygltf::Value(0);
    node.extensions["KHR_lights_punctual"] = tinygltf::Value(ext);
    addNode(node);
  }
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  if (!writer.WriteGltfSceneToStream(&model, out, false, binary)) throw std::runtime_error("tinygltf could not write");
  const std::string text = out.str();
  return {text.begin(), text.end()};
}

}  // namespace mrr::test
