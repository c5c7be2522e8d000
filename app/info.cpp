#include "app/info.h"

#include <glm/glm.hpp>

#include <cstdio>
#include <string>

namespace mrr {

namespace {

nlohmann::json vec3(const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

// "x,y,z" as --eye, --target and --light-dir take it, with enough digits to round-trip.
std::string triple(const nlohmann::json& v) {
  char text[128];
  std::snprintf(text, sizeof text, "%.9g,%.9g,%.9g", v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
  return text;
}

nlohmann::json cameraJson(const Camera& c) {
  return {{"eye", vec3(c.eye)}, {"target", vec3(c.target)}, {"up", vec3(c.up)}, {"yfov_degrees", glm::degrees(c.yfov)}};
}

std::string cameraText(const nlohmann::json& c) {
  char fov[32];
  std::snprintf(fov, sizeof fov, "%.4g", c["yfov_degrees"].get<double>());
  return "--eye " + triple(c["eye"]) + " --target " + triple(c["target"]) + " --fov " + fov;
}

std::string joined(const nlohmann::json& list) {
  std::string out;
  for (const auto& item : list) out += (out.empty() ? "" : ", ") + item.get<std::string>();
  return out.empty() ? "none" : out;
}

}  // namespace

nlohmann::json sceneInfo(const SceneRequest& request) {
  const ResolvedScene rs = resolveScene(request);
  const Scene& s = rs.scene;
  const Bounds b = s.bounds();
  nlohmann::json j;
  j["scene"] = s.name;
  j["credit"] = s.credit;
  j["triangles"] = s.triangleCount();
  j["meshes"] = s.meshes.size();
  j["bounds"] = {{"lo", vec3(b.lo)}, {"hi", vec3(b.hi)}, {"diagonal", b.diagonal()}};
  j["cameras"] = nlohmann::json::array();
  for (const Camera& c : s.cameras) j["cameras"].push_back(cameraJson(c));
  j["light"] = {{"from_scene", s.hasLight},
                {"direction", vec3(s.light.direction)},
                {"toward_light", vec3(-s.light.direction)},
                {"color", vec3(s.light.color)}};
  j["extensions_required"] = s.facts.extensionsRequired;
  j["extensions_used"] = s.facts.extensionsUsed;
  j["materials"] = {{"opaque", s.facts.opaqueMaterials}, {"mask", s.facts.maskMaterials}, {"blend", s.facts.blendMaterials}};
  j["cutouts"] = nlohmann::json::array();
  for (const Cutout& c : s.cutouts) {
    size_t opaque = 0;
    for (uint8_t bit : c.opaque) opaque += bit;
    j["cutouts"].push_back({{"width", c.width}, {"height", c.height},
                            {"opaque_share", c.opaque.empty() ? 0.0 : double(opaque) / double(c.opaque.size())}});
  }
  j["view"] = cameraJson(rs.camera);
  j["view"]["source"] = rs.cameraSource;
  // The framing a render would choose without the scene's cameras: the suggestion to start from
  // (the view itself where it is that framing).
  const Framing framing = rs.framing ? *rs.framing : frameScene(s, rs.camera.yfov, request.aspect);
  j["suggested"] = cameraJson(framing.camera);
  j["suggested"]["interior"] = framing.interior;
  j["suggested"]["enclosed_directions"] = framing.enclosedDirections;
  j["suggested"]["facing_directions"] = framing.facingDirections;
  return j;
}

void printSceneInfo(const nlohmann::json& j, std::ostream& out) {
  const auto& lo = j["bounds"]["lo"];
  const auto& hi = j["bounds"]["hi"];
  out << "scene       " << j["scene"].get<std::string>() << "\n";
  if (!j["credit"].get<std::string>().empty()) out << "credit      " << j["credit"].get<std::string>() << "\n";
  out << "geometry    " << j["triangles"] << " triangles in " << j["meshes"] << " meshes\n"
      << "bounds      " << triple(lo) << " to " << triple(hi) << "  (diagonal " << j["bounds"]["diagonal"].get<double>()
      << ")\n";
  out << "cameras     " << j["cameras"].size() << (j["cameras"].empty() ? "" : ":") << "\n";
  for (size_t i = 0; i < j["cameras"].size(); ++i) out << "  " << i << "  " << cameraText(j["cameras"][i]) << "\n";
  out << "light       " << (j["light"]["from_scene"].get<bool>() ? "the scene's" : "none in the scene: the default")
      << ", --light-dir " << triple(j["light"]["toward_light"]) << "\n";
  out << "extensions  required: " << joined(j["extensions_required"]) << "; used: " << joined(j["extensions_used"])
      << "\n";
  out << "materials   " << j["materials"]["opaque"] << " opaque, " << j["materials"]["mask"] << " alpha MASK (cutouts), "
      << j["materials"]["blend"] << " alpha BLEND\n";
  for (const auto& c : j["cutouts"])
    out << "  cutout " << c["width"] << "x" << c["height"] << ", " << 100.0 * c["opaque_share"].get<double>()
        << "% opaque\n";
  out << "view        " << cameraText(j["view"]) << "  (" << j["view"]["source"].get<std::string>() << ")\n";
  out << "suggested   " << cameraText(j["suggested"]) << "  ("
      << (j["suggested"]["interior"].get<bool>() ? "inside: the scene encloses its centre"
                                                 : "from outside, fitted to the frame")
      << ")\n";
}

}  // namespace mrr
