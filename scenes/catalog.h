#pragma once
// Resolves a --scene argument to a Scene: "builtin:NAME", a short name of one of the shared
// third-party scenes ("cornell", "arcade", "apartment", with the camera and up-axis they
// need), or a path to any .gltf/.glb file.
#include <optional>
#include <string>
#include <vector>

#include "common/scene.h"
#include "scenes/default_light.h"

namespace mrr {

struct SceneRequest {
  std::string scene = "builtin:demo";
  std::optional<bool> flipUp;           // unset: the catalogue's choice (false for files)
  std::optional<int> cameraIndex;       // into Scene::cameras
  std::optional<glm::vec3> eye, target; // explicit camera (both or neither)
  std::optional<glm::vec3> up;          // with eye and target (default +Y)
  std::optional<float> fovDegrees;      // vertical field of view
  std::optional<glm::vec3> lightToward; // --light-dir: the direction toward the light (any length > 0)
  bool skipBlendMaterials = false;      // --blend-materials skip: leave alphaMode BLEND primitives out
  float aspect = 16.0f / 9.0f;          // W/H of the image, for the default framing (frameScene)
};

struct SharedSceneInfo {
  std::string name;       // short name
  std::string file;       // relative to sharedScenesDir()
  bool flipUp = false;
  std::vector<Camera> cameras;  // good views, the first is the default
};

const std::vector<SharedSceneInfo>& sharedSceneCatalog();

// Loads the scene and picks the camera. Throws MrrError for anything wrong.
struct ResolvedScene {
  Scene scene;
  Camera camera;
  std::string cameraSource;  // where the camera came from, in words: "--eye/--target", "camera 0 of the file", ...
  std::optional<Framing> framing;  // set when the camera is the default framing (frameScene)
  // What the camera frames, at the request's aspect: makeConstants turns it into the automatic
  // radii (docs/spec.md §6). framed.size is what to pass it.
  FramedSize framed;
};
ResolvedScene resolveScene(const SceneRequest& request);
// The two halves of resolveScene, for a caller that keeps the scene and moves the camera
// (`mrr explore`): the scene with its light, and the camera the request picks in it.
Scene loadRequestedScene(const SceneRequest& request);
// `source`, when given, says where the camera came from (ResolvedScene::cameraSource).
// `framing`, when given, receives frameScene's result where the camera is the default framing.
Camera requestedCamera(const SceneRequest& request, const Scene& scene, std::string* source = nullptr,
                       std::optional<Framing>* framing = nullptr);

}  // namespace mrr
