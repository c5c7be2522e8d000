#include "scenes/catalog.h"

#include <cmath>
#include <filesystem>

#include "common/frame_params.h"
#include "common/error.h"
#include "scenes/gltf_loader.h"
#include "common/paths.h"
#include "scenes/builtin.h"
#include "scenes/default_light.h"

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

namespace {
const SharedSceneInfo* catalogEntry(const std::string& name) {
  for (const auto& entry : sharedSceneCatalog())
    if (entry.name == name) return &entry;
  return nullptr;
}
}  // namespace

namespace {

// The scene's geometry, materials and own light, as the request names them.
Scene loadGeometry(const SceneRequest& request) {
  Scene scene;
  const std::string& spec = request.scene;
  if (spec.rfind("builtin:", 0) == 0) {
    scene = makeBuiltinScene(spec.substr(8));
    if (request.flipUp.value_or(false)) flipUp(scene);
  } else {
    const SharedSceneInfo* info = catalogEntry(spec);
    LoadOptions options;
    options.skipBlend = request.skipBlendMaterials;
    std::string path = spec;
    if (info) {
      path = (std::filesystem::path(sharedScenesDir()) / info->file).string();
      require(std::filesystem::exists(path),
              "--scene " + spec + ": " + path + " not found (set MRR_SCENES_DIR to the shared scenes folder)");
      options.flipUp = request.flipUp.value_or(info->flipUp);
    } else {
      options.flipUp = request.flipUp.value_or(false);
    }
    scene = loadGltf(path, options);
  }
  return scene;
}

// The light: --light-dir points toward it; the scene's light travels the other way; a scene
// without one gets the candidate that lights the most of what `camera` (the request's view) sees.
void applyRequestedLight(Scene& scene, const SceneRequest& request, const Camera& camera) {
  if (request.lightToward) {
    const float length = glm::length(*request.lightToward);
    require(std::isfinite(length) && length > 0.0f, "--light-dir: needs a direction of non-zero length");
    // A unit direction (as frame files write it) is kept bit for bit.
    scene.light.direction = std::fabs(length - 1.0f) <= 1e-6f ? -*request.lightToward : -*request.lightToward / length;
    scene.lightOrigin.source = optionName(Param::LightDir);
  } else if (scene.hasLight) {
    scene.lightOrigin.source = "the scene";
  } else {
    // No light of its own: the candidate that lights the most of what the request's view sees
    // (the built-in default first, kept bit for bit where nothing does better).
    const DefaultLightChoice choice = chooseDefaultLight(scene, camera, request.aspect);
    scene.lightOrigin.candidate = choice.chosen;
    scene.lightOrigin.litShare = choice.shares[static_cast<size_t>(choice.chosen)];
    scene.lightOrigin.builtinLitShare = choice.shares.front();
    if (choice.chosen != 0) {
      scene.light.direction = choice.direction;
      scene.lightOrigin.source = "chosen for the view";
    }
  }
}

}  // namespace

Scene loadRequestedScene(const SceneRequest& request) {
  Scene scene = loadGeometry(request);
  applyRequestedLight(scene, request, scene.hasLight || request.lightToward ? Camera{} : requestedCamera(request, scene));
  return scene;
}

Camera requestedCamera(const SceneRequest& request, const Scene& scene, std::string* source,
                       std::optional<Framing>* framed) {
  // Camera: explicit eye/target, else the file's or built-in's camera by index, else the
  // catalogue's view, else framed from the bounds.
  const float fov = glm::radians(request.fovDegrees.value_or(60.0f));
  require(fov > 0.0f && fov < glm::radians(179.0f), "--fov: must be in (0, 179) degrees");
  if (request.eye || request.target) {
    require(request.eye && request.target, "--eye and --target must be given together");
    const Camera camera{*request.eye, *request.target, request.up.value_or(glm::vec3(0, 1, 0)), fov};
    require(glm::length(camera.target - camera.eye) > 0.0f, "--eye and --target coincide");
    require(glm::length(glm::cross(camera.target - camera.eye, camera.up)) > 0.0f,
            "--up is zero or along the view direction");
    if (source) *source = "--eye/--target";
    return camera;
  }
  std::vector<Camera> cameras = scene.cameras;
  const std::string from = cameras.empty() ? "of the scene catalogue" : "of the file";
  if (cameras.empty() && request.scene.rfind("builtin:", 0) != 0)
    if (const SharedSceneInfo* info = catalogEntry(request.scene)) cameras = info->cameras;
  Camera camera;
  std::string where;
  if (request.cameraIndex) {
    const int i = *request.cameraIndex;
    require(i >= 0 && i < static_cast<int>(cameras.size()),
            "--camera " + std::to_string(i) + ": the scene has " + std::to_string(cameras.size()) + " camera(s)");
    camera = cameras[static_cast<size_t>(i)];
    where = "camera " + std::to_string(i) + " " + from;
  } else if (!cameras.empty()) {
    camera = cameras.front();
    where = "camera 0 " + from;
  } else {
    const Framing framing = frameScene(scene, fov, request.aspect);
    if (framed) *framed = framing;
    camera = framing.camera;
    where = framing.interior   ? "default framing: inside, the scene encloses its centre"
            : framing.openSide ? "default framing: from outside, looking in through its open side"
                               : "default framing: from outside, fitted to the frame";
  }
  if (request.fovDegrees) camera.yfov = fov;
  if (source) *source = where;
  return camera;
}

ResolvedScene resolveScene(const SceneRequest& request) {
  // The camera depends on the geometry alone, so it is found once and serves the light's choice.
  ResolvedScene out;
  out.scene = loadGeometry(request);
  out.camera = requestedCamera(request, out.scene, &out.cameraSource, &out.framing);
  applyRequestedLight(out.scene, request, out.camera);
  out.framed = framedSize(out.scene, out.camera, request.aspect);
  return out;
}

}  // namespace mrr
