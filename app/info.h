#pragma once
// `mrr info SCENE`: what a scene holds and how mrr will see it, before rendering anything.
#include <nlohmann/json.hpp>

#include <ostream>

#include "scenes/catalog.h"

namespace mrr {

// The facts as JSON: source, triangles, meshes, bounds, cameras, light, extensions, materials
// by alpha mode, cutouts, and the view a render would use by default with its --eye/--target.
nlohmann::json sceneInfo(const SceneRequest& request);

// The same as text, one fact per line.
void printSceneInfo(const nlohmann::json& info, std::ostream& out);

}  // namespace mrr
