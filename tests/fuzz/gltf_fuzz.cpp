// libFuzzer target: the whole path from untrusted bytes to a validated scene — tinygltf's
// JSON/GLB parsing, then mrr's loader (node hierarchy, accessors, indices, transforms,
// normals, cameras, lights) and validateScene (NaN/Inf, ranges, degenerate geometry).
//
// The contract it checks: any input either loads into a scene every later stage can use, or
// throws MrrError with a one-line message. Anything else — a crash, a sanitizer report, an
// exception of another type, a multi-line message, a loaded scene with a non-finite bound —
// aborts and becomes a finding. Run it with scripts/fuzz.sh (docs/hardening.md).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "common/error.h"
#include "scenes/gltf_loader.h"
#include "common/scene.h"

namespace {

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "gltf_fuzz: %s\n", what.c_str());
  std::abort();
}

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<unsigned char> bytes(data, data + size);
  // A GLB starts with its magic; anything else goes to the JSON parser. The flip is taken
  // from the length so both loader branches are exercised.
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  mrr::LoadOptions options;
  options.quiet = true;
  options.flipUp = (size % 2) == 1;
  try {
    const mrr::Scene scene = mrr::loadGltfFromMemory(bytes, "fuzz.gl" + std::string(binary ? "b" : "tf"), binary, options);
    const mrr::Bounds bounds = scene.bounds();
    if (!finite(bounds.lo) || !finite(bounds.hi)) finding("a loaded scene has non-finite bounds");
    if (scene.triangleCount() == 0) finding("a loaded scene has no triangles");
    for (const mrr::Camera& camera : scene.cameras)
      if (!finite(camera.eye) || !finite(camera.target) || !(camera.yfov > 0.0f && camera.yfov < 3.1416f))
        finding("a loaded camera is not usable");
    if (!finite(scene.light.direction) || !finite(scene.light.color)) finding("the loaded light is not finite");
  } catch (const mrr::MrrError& e) {
    const std::string message = e.what();
    if (message.empty() || message.find('\n') != std::string::npos) finding("error is not one line: " + message);
  } catch (const std::exception& e) {
    finding(std::string("escaped exception that is not MrrError: ") + e.what());
  }
  return 0;
}
