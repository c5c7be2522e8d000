#pragma once
// Helpers shared by the test binaries: a fresh scratch directory per test, the shared
// scenes folder, and skipping (visibly) when a shared scene is absent.
#include <cstdint>
#include <string>
#include <vector>

#include "common/scene.h"

namespace mrr::test {

// A new empty directory under the build tree for the calling test (removed and re-made).
std::string scratchDir();

// Full path of a file in the shared scenes folder (MRR_SCENES_DIR or the CMake default).
std::string sharedScene(const std::string& relative);

// True when that file exists; tests call GTEST_SKIP() with a reason otherwise.
bool haveSharedScene(const std::string& relative);

// The whole file as bytes (empty when it cannot be read).
std::string readFile(const std::string& path);

// Standard base64 (RFC 4648, with padding), for glTF data URIs written by tests.
std::string base64(const std::vector<uint8_t>& bytes);

// A binary glTF (.glb): a JSON chunk and, when `bin` is not empty, a BIN chunk.
std::string glbFile(const std::string& json, const std::vector<uint8_t>& bin);

// The scene as a glTF 2.0 file written by tinygltf (`binary`: a .glb), buffers embedded:
// one node per mesh with positions, normals, indices and a base colour factor, one node
// per camera, and the light as a KHR_lights_punctual directional light. Used to seed the
// loader's fuzzer with the built-in scenes, and to check a write-then-load round trip.
std::vector<unsigned char> sceneToGltf(const Scene& scene, bool binary);

}  // namespace mrr::test
