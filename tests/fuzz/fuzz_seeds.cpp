// Writes the fuzzer's seed corpus: every built-in scene as .gltf and .glb (written by
// tinygltf, test_support's sceneToGltf), plus small crafted files that reach the loader's
// rarer branches (strips, fans, node hierarchies, mirrored nodes, matrices, lines, a
// camera and a light, a GLB without a BIN chunk, a meshopt-compressed triangle with its
// fallback buffer).
// Usage: fuzz_seeds DIR
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <meshoptimizer.h>

#include "scenes/builtin.h"
#include "tests/test_support.h"

namespace fs = std::filesystem;

namespace {

void write(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

// One triangle, positions in a data: URI; `extra` is spliced into the top-level object.
std::string crafted(const std::string& primitive, const std::string& nodes, const std::string& extra = "") {
  static const std::string triangle = [] {
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::vector<uint8_t> bytes(sizeof p);
    std::memcpy(bytes.data(), p, sizeof p);
    bytes.insert(bytes.end(), {0, 0, 1, 0, 2, 0, 0, 0});  // uint16 indices 0 1 2 + padding
    return mrr::test::base64(bytes);
  }();
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":)" + nodes +
         R"(,"meshes":[{"primitives":[)" + primitive + R"(]}],
"buffers":[{"byteLength":44,"uri":"data:application/octet-stream;base64,)" + triangle + R"("}],
"bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}])" + extra + "}";
}

// The triangle as EXT_meshopt_compression streams (vertices, then triangles) in buffer 0,
// decoding into buffer 1, a fallback without uri or data, as gltfpack writes it.
std::string meshoptTriangle() {
  const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const unsigned int indices[3] = {0, 1, 2};
  std::vector<uint8_t> vertices(meshopt_encodeVertexBufferBound(3, 12));
  vertices.resize(meshopt_encodeVertexBuffer(vertices.data(), vertices.size(), p, 3, 12));
  std::vector<uint8_t> triangles(meshopt_encodeIndexBufferBound(3, 3));
  triangles.resize(meshopt_encodeIndexBuffer(triangles.data(), triangles.size(), indices, 3));
  std::vector<uint8_t> bin = vertices;
  while (bin.size() % 4 != 0) bin.push_back(0);
  const size_t offset = bin.size();
  bin.insert(bin.end(), triangles.begin(), triangles.end());
  const auto n = [](size_t v) { return std::to_string(v); };
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
"extensionsUsed":["EXT_meshopt_compression"],"extensionsRequired":["EXT_meshopt_compression"],
"buffers":[{"byteLength":)" + n(bin.size()) + R"(,"uri":"data:application/octet-stream;base64,)" +
         mrr::test::base64(bin) + R"("},
{"byteLength":48,"extensions":{"EXT_meshopt_compression":{"fallback":true}}}],
"bufferViews":[{"buffer":1,"byteLength":36,"byteStride":12,"extensions":{"EXT_meshopt_compression":
{"buffer":0,"byteLength":)" + n(vertices.size()) + R"(,"byteStride":12,"count":3,"mode":"ATTRIBUTES"}}},
{"buffer":1,"byteOffset":36,"byteLength":12,"extensions":{"EXT_meshopt_compression":
{"buffer":0,"byteOffset":)" + n(offset) + R"(,"byteLength":)" + n(triangles.size()) + R"(,"byteStride":4,"count":3,"mode":"TRIANGLES"}}}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},
{"bufferView":1,"componentType":5125,"count":3,"type":"SCALAR"}]})";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_seeds DIR\n";
    return 2;
  }
  const fs::path dir = argv[1];
  fs::create_directories(dir);
  int count = 0;
  for (const std::string& name : mrr::builtinSceneNames())
    for (const bool binary : {false, true}) {
      const auto bytes = mrr::test::sceneToGltf(mrr::makeBuiltinScene(name), binary);
      write(dir / (name + (binary ? ".glb" : ".gltf")), std::string(bytes.begin(), bytes.end()));
      ++count;
    }
  const std::string plain = R"({"attributes":{"POSITION":0},"indices":1})";
  const std::string node = R"([{"mesh":0}])";
  write(dir / "triangle.gltf", crafted(plain, node));
  write(dir / "strip.gltf", crafted(R"({"attributes":{"POSITION":0},"mode":5})", node));
  write(dir / "fan.gltf", crafted(R"({"attributes":{"POSITION":0},"mode":6})", node));
  write(dir / "lines.gltf", crafted(R"({"attributes":{"POSITION":0},"mode":1},)" + plain, node));
  write(dir / "hierarchy.gltf",
        crafted(plain, R"([{"children":[1],"translation":[1,2,3],"rotation":[0,0.7071,0,0.7071]},
{"mesh":0,"scale":[2,-1,1]}])"));
  write(dir / "matrix.gltf", crafted(plain, R"([{"mesh":0,"matrix":[1,0,0,0,0,1,0,0,0,0,-1,0,0,0,0,1]}])"));
  write(dir / "camera_light.gltf",
        crafted(plain, R"([{"mesh":0,"children":[1,2]},{"camera":0,"translation":[0,0,5]},
{"extensions":{"KHR_lights_punctual":{"light":0}},"rotation":[-0.38,0,0,0.92]}])",
                R"(,"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"znear":0.1}}],
"extensionsUsed":["KHR_lights_punctual"],
"extensions":{"KHR_lights_punctual":{"lights":[{"type":"directional","color":[1,0.9,0.8],"intensity":3}]}})"));
  write(dir / "glb_of_triangle.glb", mrr::test::glbFile(crafted(plain, node), {}));
  write(dir / "meshopt.gltf", meshoptTriangle());
  std::cerr << "fuzz_seeds: wrote " << count + 9 << " seeds to " << dir.string() << "\n";
  return 0;
}
