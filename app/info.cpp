#include "app/info.h"

#include <glm/glm.hpp>

#include <cstdio>
#include <iostream>
#include <string>

#include "app/commands.h"
#include "scenes/builtin.h"
#include "common/error.h"
#include "common/frame_params.h"
#include "frontend/options.h"

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
  return optionName(Param::Eye) + " " + triple(c["eye"]) + " " + optionName(Param::Target) + " " + triple(c["target"]) +
         " " + optionName(Param::Fov) + " " + fov;
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
  if (request.scene.rfind("builtin:", 0) == 0) j["description"] = builtinSceneDescription(request.scene.substr(8));
  j["triangles"] = s.triangleCount();
  j["meshes"] = s.meshes.size();
  j["bounds"] = {{"lo", vec3(b.lo)}, {"hi", vec3(b.hi)}, {"diagonal", b.diagonal()}};
  j["cameras"] = nlohmann::json::array();
  for (const Camera& c : s.cameras) j["cameras"].push_back(cameraJson(c));
  j["light"] = {{"from_scene", s.hasLight},
                {"direction", vec3(s.light.direction)},
                {"toward_light", vec3(-s.light.direction)},
                {"color", vec3(s.light.color)},
                {"source", s.lightOrigin.source},  // "the scene", "--light-dir", "built-in default", "chosen for the view"
                {"lit_share", s.lightOrigin.litShare},  // of the view's visible surface; -1: not measured
                {"builtin_lit_share", s.lightOrigin.builtinLitShare}};
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
  // The automatic radii this view gets (docs/spec.md §6): fractions of what it frames.
  j["radii"] = {{"framed_size", rs.framed.size},
                {"median_depth", rs.framed.medianDepth},
                {"ssao_radius", SsaoSettings::kAutoRadiusFraction * rs.framed.size},
                {"ssgi_radius", SsgiSettings::kAutoRadiusFraction * rs.framed.size}};
  // The framing a render would choose without the scene's cameras: the suggestion to start from
  // (the view itself where it is that framing).
  const Framing framing = rs.framing ? *rs.framing : frameScene(s, rs.camera.yfov, request.aspect);
  j["suggested"] = cameraJson(framing.camera);
  j["suggested"]["interior"] = framing.interior;
  j["suggested"]["open_side"] = framing.openSide;
  j["suggested"]["enclosed_directions"] = framing.enclosedDirections;
  j["suggested"]["facing_directions"] = framing.facingDirections;
  return j;
}

void printSceneInfo(const nlohmann::json& j, std::ostream& out) {
  const auto& lo = j["bounds"]["lo"];
  const auto& hi = j["bounds"]["hi"];
  out << "scene       " << j["scene"].get<std::string>() << "\n";
  if (!j["credit"].get<std::string>().empty()) out << "credit      " << j["credit"].get<std::string>() << "\n";
  if (j.contains("description")) out << "what        " << j["description"].get<std::string>() << "\n";
  out << "geometry    " << j["triangles"] << " triangles in " << j["meshes"] << " meshes\n"
      << "bounds      " << triple(lo) << " to " << triple(hi) << "  (diagonal " << j["bounds"]["diagonal"].get<double>()
      << ")\n";
  out << "cameras     " << j["cameras"].size() << (j["cameras"].empty() ? "" : ":") << "\n";
  for (size_t i = 0; i < j["cameras"].size(); ++i) out << "  " << i << "  " << cameraText(j["cameras"][i]) << "\n";
  out << "light       " << j["light"]["source"].get<std::string>() << ", --light-dir " << triple(j["light"]["toward_light"]);
  if (const double lit = j["light"]["lit_share"].get<double>(); lit >= 0.0) {
    char share[96];
    std::snprintf(share, sizeof share, "; lights %.0f%% of the visible surface", 100.0 * lit);
    out << share;
    if (const double builtin = j["light"]["builtin_lit_share"].get<double>(); builtin >= 0.0 && j["light"]["source"] != "built-in default") {
      std::snprintf(share, sizeof share, " (the built-in default: %.0f%%)", 100.0 * builtin);
      out << share;
    }
  }
  out << "\n";
  out << "extensions  required: " << joined(j["extensions_required"]) << "; used: " << joined(j["extensions_used"])
      << "\n";
  out << "materials   " << j["materials"]["opaque"] << " opaque, " << j["materials"]["mask"] << " alpha MASK (cutouts), "
      << j["materials"]["blend"] << " alpha BLEND\n";
  for (const auto& c : j["cutouts"])
    out << "  cutout " << c["width"] << "x" << c["height"] << ", " << 100.0 * c["opaque_share"].get<double>()
        << "% opaque\n";
  out << "view        " << cameraText(j["view"]) << "  (" << j["view"]["source"].get<std::string>() << ")\n";
  {
    const auto& r = j["radii"];
    char radii[256];
    std::snprintf(radii, sizeof radii,
                  "automatic: ssao R %.3g, ssgi R %.3g  (%.0f%% and %.0f%% of the framed size %.3g: the view's height "
                  "at its median surface depth %.3g)",
                  r["ssao_radius"].get<double>(), r["ssgi_radius"].get<double>(), 100.0 * SsaoSettings::kAutoRadiusFraction,
                  100.0 * SsgiSettings::kAutoRadiusFraction, r["framed_size"].get<double>(), r["median_depth"].get<double>());
    out << "radii       " << radii << "\n";
  }
  out << "suggested   " << cameraText(j["suggested"]) << "  ("
      << (j["suggested"]["interior"].get<bool>() ? "inside: the scene encloses its centre"
                                                 : "from outside, fitted to the frame")
      << ")\n";
}

void addInfoCommand(CLI::App& app, InfoCommand& c) {
  c.command = app.add_subcommand(
      "info", "what a scene holds: bounds, triangles, cameras, light, extensions, materials, and a suggested view");
  c.command->add_option("scene", c.request.scene, std::string(paramInfo(Param::Scene).help))->required();
  c.command->add_option(optionName(Param::Size), c.size, "WxH of the image the suggested view is fitted to")
      ->capture_default_str();
  c.command->add_option(optionName(Param::Fov), c.fov, paramHelp(Param::Fov));
  c.command->add_flag(optionName(Param::FlipUp), c.flipUp, paramHelp(Param::FlipUp));
  c.command->add_flag(optionName(Param::NoFlipUp), c.noFlipUp, paramHelp(Param::NoFlipUp));
  c.command->add_option(optionName(Param::BlendMaterials), c.blendMaterials, "opaque or skip, as render takes it")
      ->capture_default_str();
  c.command->add_flag("--json", c.json, "print JSON instead of text");
}

int runInfoCommand(InfoCommand& c) {
  const auto [w, h] = parseSize(c.size);
  require(w >= 1 && h >= 1 && w <= kMaxImageSize && h <= kMaxImageSize,
          optionName(Param::Size) + " " + c.size + ": each side must be in [1, " + std::to_string(kMaxImageSize) + "]");
  c.request.aspect = static_cast<float>(w) / static_cast<float>(h);
  c.request.fovDegrees = c.fov;
  if (c.flipUp) c.request.flipUp = true;
  if (c.noFlipUp) c.request.flipUp = false;
  require(c.blendMaterials == "opaque" || c.blendMaterials == "skip",
          optionName(Param::BlendMaterials) + " " + c.blendMaterials + ": expected opaque or skip");
  c.request.skipBlendMaterials = c.blendMaterials == "skip";
  const nlohmann::json facts = sceneInfo(c.request);
  if (c.json)
    std::cout << facts.dump(2) << "\n";
  else
    printSceneInfo(facts, std::cout);
  return 0;
}

}  // namespace mrr
