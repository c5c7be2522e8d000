#include "scenes/catalog.h"

#include <cmath>
#include <filesystem>

#include "common/error.h"
#include "common/gltf_loader.h"
#include "common/paths.h"
#include "scenes/builtin.h"

namespace mrr {

const std::vector<SharedSceneInfo>& sharedSceneCatalog() {
  // Cameras chosen by looking at the renders (docs/scenes.md); the first is the default.
  static const std::vector<SharedSceneInfo> catalog = {
      {"cornell", "cornell-box/CornellBox-Original.gltf", false,
       {lookAt({0, 1, 3.5f}, {0, 1, 0}, 45.0f)}},
      {"arcade", "sascha-arcade/subpass_scene_opaque.gltf", true,
       {lookAt({0.0f, 3.5f, 9.5f}, {0.0f, 2.0f, 0.0f}, 60.0f)}},
      {"apartment", "dream-apartment/dream-apartment.glb", false,
       {lookAt({12.2f, 1.7f, -7.6f}, {7.0f, 0.8f, -4.0f}, 60.0f),   // kitchen and dining table
        lookAt({7.3f, 1.6f, -3.6f}, {12.0f, 0.8f, -7.5f}, 60.0f)}},  // kitchen island
  };
  return catalog;
}

ResolvedScene resolveScene(const SceneRequest& request) {
  ResolvedScene out;
  const std::string& spec = request.scene;
  std::vector<Camera> catalogCameras;
  if (spec.rfind("builtin:", 0) == 0) {
    out.scene = makeBuiltinScene(spec.substr(8));
    if (request.flipUp.value_or(false)) flipUp(out.scene);
  } else {
    const SharedSceneInfo* info = nullptr;
    for (const auto& entry : sharedSceneCatalog())
      if (entry.name == spec) info = &entry;
    LoadOptions options;
    options.skipBlend = request.skipBlendMaterials;
    std::string path = spec;
    if (info) {
      path = (std::filesystem::path(sharedScenesDir()) / info->file).string();
      require(std::filesystem::exists(path),
              "--scene " + spec + ": " + path + " not found (set MRR_SCENES_DIR to the shared scenes folder)");
      options.flipUp = request.flipUp.value_or(info->flipUp);
      catalogCameras = info->cameras;
    } else {
      options.flipUp = request.flipUp.value_or(false);
    }
    out.scene = loadGltf(path, options);
  }
  // The light: --light-dir points toward it; the scene's light travels the other way.
  if (request.lightToward) {
    const float length = glm::length(*request.lightToward);
    require(std::isfinite(length) && length > 0.0f, "--light-dir: needs a direction of non-zero length");
    // A unit direction (as frame files write it) is kept bit for bit.
    out.scene.light.direction = std::fabs(length - 1.0f) <= 1e-6f ? -*request.lightToward : -*request.lightToward / length;
  }
  // Camera: explicit eye/target, else the file's or built-in's camera by index, else the
  // catalogue's view, else framed from the bounds.
  const float fov = glm::radians(request.fovDegrees.value_or(60.0f));
  require(fov > 0.0f && fov < glm::radians(179.0f), "--fov: must be in (0, 179) degrees");
  if (request.eye || request.target) {
    require(request.eye && request.target, "--eye and --target must be given together");
    out.camera = Camera{*request.eye, *request.target, request.up.value_or(glm::vec3(0, 1, 0)), fov};
    require(glm::length(out.camera.target - out.camera.eye) > 0.0f, "--eye and --target coincide");
    require(glm::length(glm::cross(out.camera.target - out.camera.eye, out.camera.up)) > 0.0f,
            "--up is zero or along the view direction");
    out.cameraSource = "--eye/--target";
    return out;
  }
  std::vector<Camera> cameras = out.scene.cameras;
  const std::string from = cameras.empty() ? "of the scene catalogue" : "of the file";
  if (cameras.empty()) cameras = catalogCameras;
  if (request.cameraIndex) {
    const int i = *request.cameraIndex;
    require(i >= 0 && i < static_cast<int>(cameras.size()),
            "--camera " + std::to_string(i) + ": the scene has " + std::to_string(cameras.size()) + " camera(s)");
    out.camera = cameras[static_cast<size_t>(i)];
    out.cameraSource = "camera " + std::to_string(i) + " " + from;
  } else if (!cameras.empty()) {
    out.camera = cameras.front();
    out.cameraSource = "camera 0 " + from;
  } else {
    const Framing framing = frameScene(out.scene, fov, request.aspect);
    out.camera = framing.camera;
    out.cameraSource = framing.interior ? "default framing: inside, the scene encloses its centre"
                                        : "default framing: from outside, fitted to the frame";
  }
  if (request.fovDegrees) out.camera.yfov = fov;
  return out;
}

}  // namespace mrr
