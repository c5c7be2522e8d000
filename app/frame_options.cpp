#include "app/frame_options.h"

#include <nlohmann/json.hpp>

#include <cmath>

#include "app/frame_file.h"
#include "app/options.h"
#include "common/error.h"
#include "gpu/pipeline.h"
#include "scenes/builtin.h"

namespace mrr {

void FrameOptions::add(CLI::App& app) {
  std::string builtins;
  for (const auto& n : builtinSceneNames()) builtins += " builtin:" + n;
  app.add_option("--scene", scene,
                 "builtin:NAME, a shared scene (cornell, arcade, apartment) or a .gltf/.glb path. Built-ins:" + builtins)
      ->capture_default_str();
  app.add_option("--effect", effect, "ssao, ssm (PCSS soft shadows) or ssgi (indirect light)")->capture_default_str();
  app.add_option("--method,--mode", mode,
                 "mrr (= multires, the method), full (the reference), or a peer: uniform-1, uniform-2 (one coarse "
                 "level, joint bilateral upsampling), tiles (16x16 VRS-style rates)")
      ->capture_default_str();
  app.add_option("--never-slower", neverSlower,
                 "mrr: shade the frame at full res when the cost model predicts no gain: on|off (default on; "
                 "compare: off, it validates every stage)");
  app.add_option("--cost-model", costModelFile,
                 "the never-slower rule's costs, a JSON written by `mrr bench --calibrate` (default: built in)");
  app.add_option("--path", path, "cpu (the oracle) or gpu (the OpenGL 3.3 port, headless EGL); probe: also both")
      ->capture_default_str();
  app.add_option("--gl-device", glDevice, "gpu: the EGL device index (default: the first that gives GL 3.3 core)");
  app.add_option("--gpu-timing", gpuTiming,
                 "gpu: stage timings by glFinish + wall clock (wall), GL_TIME_ELAPSED queries (query), or auto: "
                 "wall on llvmpipe, whose queries are wrong, query elsewhere")
      ->capture_default_str();
  app.add_option("--size", size, "WIDTHxHEIGHT, each side in [1, 16384]")->capture_default_str();
  app.add_option("--samples", samples,
                 "samples per pixel (default ssao 64, ssm 196, ssgi 288; ssao 1..1024, ssm a square n*n up to 1024, "
                 "ssgi 1..8192)")
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.add_option("--threads", threads, "worker threads (0 = all cores); results are identical for any count");
  app.add_option("--camera", camera, "index into the scene's cameras");
  app.add_option("--eye", eye, "camera position x,y,z (with --target)");
  app.add_option("--target", target, "camera target x,y,z (with --eye)");
  app.add_option("--up", up, "camera up x,y,z (with --eye and --target; default 0,1,0)");
  app.add_option("--fov", fov, "vertical field of view, degrees");
  app.add_option("--frame", frameFile,
                 "a frame file (JSON, as render --frame-out writes it): scene, camera, light, size, effect, samples "
                 "and every parameter; options given here win");
  app.add_option("--blend-materials", blendMaterials,
                 "glTF materials with alphaMode BLEND: opaque (drawn as solid) or skip (left out)")
      ->capture_default_str();
  app.add_option("--light-dir", lightDir,
                 "x,y,z: the direction toward the directional light, world space (default: the scene's light, or "
                 "for a scene without one the built-in default)");
  app.add_flag("--flip-up", flipUp, "rotate the scene 180 degrees about X (files authored Y-down)");
  app.add_flag("--no-flip-up", noFlipUp, "do not flip, even where the scene catalogue would");
  app.add_option("--ao-radius", aoRadius, "SSAO radius in world units (0 = 3% of the scene diagonal)");
  app.add_option("--shadow-map-size", shadowMapSize, "ssm/ssgi: shadow map texels per side (default 2048)");
  app.add_option("--light-angle", lightAngle, "ssm: the light's angular diameter in radians (default 0.05)");
  app.add_option("--gi-radius", giRadius, "ssgi: sample radius in world units (0 = 6% of the scene diagonal)");
  app.add_flag("--ao-texel-depth", texelDepth,
               "SSAO: compare against the texel-centre depth instead of the tangent plane (the classic test)");
  app.add_option("--tau-n", tauN, "normal-edge threshold on 1 - N.N (default 0.1)");
  app.add_option("--tau-z", tauZ, "depth-edge threshold on |second difference of 1/z| / (1/z) (default 0.02)");
  app.add_option("--disable-level", disabledLevels, "disable level 1, 2 or 3 (repeatable)");
  app.add_option("--sigma2", sigma2,
                 "the mask blur's variance per level, s0,s1,s2,s3 in level pixels, each in [0, 64] (default: the "
                 "paper's Table 1 for the effect)");
  app.add_option("--weights", weights,
                 "the blend weight w per level, w0,w1,w2,w3, each >= 0: alpha = min(a w, 1) (default: Table 1)");
  app.add_option("--memory-limit", memoryLimitGiB,
                 "GiB the run may plan to use (default: MRR_MEMORY_LIMIT, else 3/4 of physical memory)");
  app.add_flag("-q,--quiet", quiet, "no progress lines on stderr");
}

Settings FrameOptions::settings() const {
  Settings s = defaultSettings(parseEffect(effect));
  s.mode = parseMode(mode);
  require(neverSlower.empty() || neverSlower == "on" || neverSlower == "off",
          "--never-slower " + neverSlower + ": expected on or off");
  s.neverSlower = neverSlower.empty() ? neverSlowerDefault : neverSlower == "on";
  const auto [w, h] = parseSize(size);
  s.width = w;
  s.height = h;
  if (samples) s.setSamples(*samples);
  s.ssao.radius = aoRadius;
  s.ssgi.radius = giRadius;
  if (shadowMapSize) s.ssm.shadowMapSize = *shadowMapSize;
  if (lightAngle) s.ssm.lightAngle = *lightAngle;
  s.ssao.tangentPlaneDepth = !texelDepth;
  if (tauN) s.edges.normalThreshold = *tauN;
  if (tauZ) s.edges.depthThreshold = *tauZ;
  const auto perLevel = [](const std::string& text, const std::string& option, auto set) {
    if (text.empty()) return;
    std::vector<float> values;
    std::string rest = text;
    bool ok = true;
    while (ok) {
      const size_t comma = rest.find(',');
      const std::string item = rest.substr(0, comma);
      try {
        size_t used = 0;
        values.push_back(std::stof(item, &used));
        ok = used == item.size() && std::isfinite(values.back());
      } catch (const std::exception&) {
        ok = false;
      }
      if (comma == std::string::npos) break;
      rest = rest.substr(comma + 1);
    }
    require(ok && values.size() == kLevelCount,
            option + " " + text + ": expected " + std::to_string(kLevelCount) + " numbers, one per level, e.g. 1,1,1,1");
    for (size_t l = 0; l < values.size(); ++l) set(l, values[l]);
  };
  perLevel(sigma2, "--sigma2", [&](size_t l, float v) {
    require(v >= 0.0f && v <= 64.0f, "--sigma2 " + sigma2 + ": level " + std::to_string(l) + "'s variance must be in [0, 64]");
    s.levels[l].sigma2 = v;
  });
  perLevel(weights, "--weights", [&](size_t l, float v) {
    require(v >= 0.0f, "--weights " + weights + ": level " + std::to_string(l) + "'s weight must be >= 0");
    s.levels[l].weight = v;
  });
  for (int l : disabledLevels) {
    require(l >= 1 && l < kLevelCount, "--disable-level " + std::to_string(l) + ": must be 1, 2 or 3");
    s.levels[static_cast<size_t>(l)].enabled = false;
  }
  validateSettings(s);
  return s;
}

CostModel FrameOptions::costModel(const std::string& forPath) const {
  return costModelFile.empty() ? CostModel::defaults(forPath) : CostModel::fromFile(costModelFile);
}

SceneRequest FrameOptions::sceneRequest() const {
  SceneRequest r;
  r.scene = scene;
  if (flipUp) r.flipUp = true;
  if (noFlipUp) r.flipUp = false;
  r.cameraIndex = camera;
  if (!eye.empty()) r.eye = parseVec3(eye, "--eye");
  if (!target.empty()) r.target = parseVec3(target, "--target");
  if (!up.empty()) r.up = parseVec3(up, "--up");
  r.fovDegrees = fov;
  if (!lightDir.empty()) r.lightToward = parseVec3(lightDir, "--light-dir");
  require(blendMaterials == "opaque" || blendMaterials == "skip",
          "--blend-materials " + blendMaterials + ": expected opaque or skip");
  r.skipBlendMaterials = blendMaterials == "skip";
  const auto [w, h] = parseSize(size);
  r.aspect = static_cast<float>(w) / static_cast<float>(h);
  return r;
}

nlohmann::json FrameOptions::frame(const ResolvedScene& rs, const Settings& s) const {
  auto triple = [](const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  std::string sigma2s, weightList;
  for (size_t l = 0; l < s.levels.size(); ++l) {
    sigma2s += (l ? "," : "") + exactFloat(s.levels[l].sigma2);
    weightList += (l ? "," : "") + exactFloat(s.levels[l].weight);
  }
  nlohmann::json j = {{"mrr_frame", 1},
                      {"scene", scene},
                      {"effect", toString(s.effect)},
                      {"method", toString(s.mode)},
                      {"size", std::to_string(s.width) + "x" + std::to_string(s.height)},
                      {"samples", s.samples()},
                      {"eye", triple(rs.camera.eye)},
                      {"target", triple(rs.camera.target)},
                      {"up", triple(rs.camera.up)},
                      {"fov", exactDegrees(rs.camera.yfov)},
                      {"light_dir", triple(-rs.scene.light.direction)},
                      {"light_angle", s.ssm.lightAngle},
                      {"shadow_map_size", s.ssm.shadowMapSize},
                      {"ao_radius", s.ssao.radius},
                      {"gi_radius", s.ssgi.radius},
                      {"ao_texel_depth", !s.ssao.tangentPlaneDepth},
                      {"tau_n", s.edges.normalThreshold},
                      {"tau_z", s.edges.depthThreshold},
                      {"sigma2", sigma2s},
                      {"weights", weightList},
                      {"disable_level", nlohmann::json::array()},
                      {"never_slower", s.neverSlower ? "on" : "off"},
                      {"blend_materials", blendMaterials}};
  for (int l = 1; l < kLevelCount; ++l)
    if (!s.levels[static_cast<size_t>(l)].enabled) j["disable_level"].push_back(l);
  if (flipUp || noFlipUp) j["flip_up"] = flipUp;
  return j;
}

void FrameOptions::checkPath(bool bothAllowed) const {
  gpu::parseGpuTiming(gpuTiming);  // validates the name
  if (bothAllowed && path == "both") return;
  require(path == "cpu" || path == "gpu",
          "--path " + path + ": unknown path (expected cpu or gpu" + (bothAllowed ? ", or both" : "") + ")");
}

}  // namespace mrr
