#include "frontend/frame_options.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <type_traits>
#include <variant>

#include "frontend/frame_file.h"
#include "frontend/options.h"
#include "common/error.h"
#include "common/image_io.h"
#include "gpu/pipeline.h"
#include "scenes/builtin.h"

namespace mrr {

namespace {

// The FrameOptions field a row of the frame-parameter table sets, for the rows the front end
// resolves itself (the others set a Settings field through `given`: common/frame_params.h).
using Field = std::variant<std::string FrameOptions::*, int FrameOptions::*, std::optional<int> FrameOptions::*,
                           std::optional<float> FrameOptions::*, std::optional<double> FrameOptions::*,
                           bool FrameOptions::*, std::vector<int> FrameOptions::*>;

Field bindField(Param param) {
  using F = FrameOptions;
  switch (param) {
    case Param::Scene: return &F::scene;
    case Param::Effect: return &F::effect;
    case Param::Method: return &F::mode;
    case Param::CostModel: return &F::costModelFile;
    case Param::Path: return &F::path;
    case Param::GlDevice: return &F::glDevice;
    case Param::GpuTiming: return &F::gpuTiming;
    case Param::Size: return &F::size;
    case Param::Samples: return &F::samples;
    case Param::Threads: return &F::threads;
    case Param::CoarseGbuffer: return &F::coarseGBuffer;
    case Param::Camera: return &F::camera;
    case Param::Eye: return &F::eye;
    case Param::Target: return &F::target;
    case Param::Up: return &F::up;
    case Param::Fov: return &F::fov;
    case Param::Frame: return &F::frameFile;
    case Param::BlendMaterials: return &F::blendMaterials;
    case Param::LightDir: return &F::lightDir;
    case Param::FlipUp: return &F::flipUp;
    case Param::NoFlipUp: return &F::noFlipUp;
    case Param::AoTexelDepth: return &F::texelDepth;
    case Param::DisableLevel: return &F::disabledLevels;
    case Param::Gaze: return &F::gaze;
    case Param::PrevFrame: return &F::prevFrame;
    case Param::Pan: return &F::pan;
    case Param::MemoryLimit: return &F::memoryLimitGiB;
    case Param::Quiet: return &F::quiet;
    default: break;
  }
  throw MrrError("internal: no FrameOptions field for " + optionName(param));
}

// "--tau-n" plus the row's aliases, as CLI11 takes names ("-q,--quiet").
std::string cliNames(const FrameParamInfo& p) {
  return (p.alias.empty() ? "" : std::string(p.alias) + ",") + optionName(p.param);
}

}  // namespace

void FrameOptions::add(CLI::App& app) {
  for (const FrameParamInfo& p : frameParams()) {
    const std::string names = cliNames(p);
    const Param param = p.param;
    if (p.field) {  // a Settings field: its text, set (and checked) by setParam in settings()
      if (p.kind == ParamKind::Flag)
        app.add_flag_callback(names, [this, param] { given[param] = "1"; }, paramHelp(param));
      else
        app.add_option_function<std::string>(names, [this, param](const std::string& v) { given[param] = v; },
                                             paramHelp(param))
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
      continue;
    }
    std::visit(
        [&](auto member) {
          auto& field = this->*member;
          using T = std::decay_t<decltype(field)>;
          if constexpr (std::is_same_v<T, bool>) {
            app.add_flag(names, field, paramHelp(param));
          } else if constexpr (std::is_same_v<T, std::string>) {
            // The front end's own default (the member's initial value) is the one shown.
            app.add_option(names, field, paramHelp(param, field));
          } else {
            CLI::Option* o = app.add_option(names, field, paramHelp(param));
            if constexpr (std::is_same_v<T, std::optional<int>> || std::is_same_v<T, std::optional<float>>)
              o->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
          }
        },
        bindField(param));
  }
}

Settings FrameOptions::settings() const {
  Settings s = defaultSettings(parseEffect(effect));
  s.mode = parseMode(mode);
  s.neverSlower = neverSlowerDefault;
  // Every row with a Settings field that was given: parsed and checked against its row's range.
  for (const auto& [param, text] : given) setParam(s, param, text);
  const auto [w, h] = parseSize(size);
  s.width = w;
  s.height = h;
  if (samples) s.setSamples(*samples);
  require(coarseGBuffer == "subsample" || coarseGBuffer == "render",
          optionName(Param::CoarseGbuffer) + " " + coarseGBuffer + ": expected subsample or render");
  s.renderCoarseGBuffer = coarseGBuffer == "render";
  s.ssao.tangentPlaneDepth = !texelDepth;
  // SPEC §13: the gaze and the previous frame.
  if (!gaze.empty()) {
    int gx = 0, gy = 0;
    char comma = 0, rest = 0;
    require(std::sscanf(gaze.c_str(), "%d%c%d%c", &gx, &comma, &gy, &rest) == 3 && comma == ',',
            optionName(Param::Gaze) + " " + gaze + ": expected X,Y, a full-res pixel (whole numbers)");
    s.foveation.gaze = true;
    s.foveation.gazeX = gx;
    s.foveation.gazeY = gy;
  }
  if (pan && *pan != 0.0f) {
    require(paramInfo(Param::Pan).range.contains(*pan), optionName(Param::Pan) + " " + exactFloat(*pan) + ": " + rangeRule(Param::Pan));
    require(prevFrame.empty(), optionName(Param::Pan) + ": not with " + optionName(Param::PrevFrame) +
                                   " (each gives the previous camera; give one)");
  }
  if (!prevFrame.empty()) {
    const std::string where = optionName(Param::PrevFrame) + " " + prevFrame;
    const nlohmann::json prev = readJsonObjectFile(prevFrame, optionName(Param::PrevFrame));
    frameArgs(prev, where);  // its keys and values, as --frame checks them
    const auto text = [&](Param p) {
      const std::string key(paramInfo(p).key);
      require(prev.contains(key) && prev[key].is_string(), where + ": has no \"" + key + "\" (write it with render --frame-out)");
      return prev[key].get<std::string>();
    };
    require(text(Param::Scene) == scene, where + ": its scene " + text(Param::Scene) + " is not this frame's " + scene);
    const std::string prevSize = text(Param::Size);
    require(parseSize(prevSize) == parseSize(size), where + ": its size " + prevSize + " is not this frame's " + size);
    const auto vec = [&](Param p) {
      const std::string key(paramInfo(p).key);
      require(prev.contains(key), where + ": has no \"" + key + "\" (write it with render --frame-out)");
      const nlohmann::json& v = prev[key];
      return glm::vec3(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
    };
    s.foveation.motion = true;
    s.foveation.prevEye = vec(Param::Eye);
    s.foveation.prevTarget = vec(Param::Target);
    s.foveation.prevUp = vec(Param::Up);
    const std::string fovKey(paramInfo(Param::Fov).key);
    require(prev.contains(fovKey) && prev[fovKey].is_number(), where + ": has no \"" + fovKey + "\"");
    s.foveation.prevYfov = glm::radians(prev[fovKey].get<float>());
  }
  if (pan && *pan != 0.0f) {  // motion without a file: the previous view is this one, panned (previousView)
    s.foveation.motion = true;
    s.foveation.panned = true;
    s.foveation.pan = *pan;
  }
  for (int l : disabledLevels) {
    require(l >= 1 && l < kLevelCount, optionName(Param::DisableLevel) + " " + std::to_string(l) + ": must be 1, 2 or 3");
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
  if (!eye.empty()) r.eye = parseVec3(eye, optionName(Param::Eye));
  if (!target.empty()) r.target = parseVec3(target, optionName(Param::Target));
  if (!up.empty()) r.up = parseVec3(up, optionName(Param::Up));
  r.fovDegrees = fov;
  if (!lightDir.empty()) r.lightToward = parseVec3(lightDir, optionName(Param::LightDir));
  require(blendMaterials == "opaque" || blendMaterials == "skip",
          optionName(Param::BlendMaterials) + " " + blendMaterials + ": expected opaque or skip");
  r.skipBlendMaterials = blendMaterials == "skip";
  const auto [w, h] = parseSize(size);
  r.aspect = static_cast<float>(w) / static_cast<float>(h);
  return r;
}

namespace {

// A frame-file row's value for this frame: the camera and light as resolved, the parameters as
// the settings hold them (numbers that round-trip exactly); null leaves the key out.
nlohmann::json frameValue(Param param, const FrameOptions& fo, const ResolvedScene* rs, const Settings& s) {
  auto triple = [](const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  const FrameParamInfo& p = paramInfo(param);
  // A parameter a method owns, in the files of that method only.
  if (ownedByAMethod(param) && !methodInfo(s.mode).owns(param)) return nullptr;
  if (p.field) {  // its Settings field, as its kind writes it
    const std::string text = paramText(s, param);
    switch (p.kind) {
      case ParamKind::Int:
        if (param == Param::Seed && s.seed == 0) return nullptr;  // absent: 0, mrr's own sampling
        return std::stoll(text);
      case ParamKind::Number: return std::stof(text);
      case ParamKind::Flag: return text == "1";
      case ParamKind::Switch:
        if (param == Param::Foveate && !s.foveation.gaze) return nullptr;  // with a gaze only
        return text;
      default: return text;
    }
  }
  switch (param) {
    case Param::Scene: return fo.scene;
    case Param::Effect: return toString(s.effect);
    case Param::Method: return toString(s.mode);
    case Param::Size: return std::to_string(s.width) + "x" + std::to_string(s.height);
    case Param::Samples: return s.samples();
    case Param::CoarseGbuffer: return s.renderCoarseGBuffer ? nlohmann::json("render") : nlohmann::json();  // absent: subsample
    // The camera and light as resolved (a cache key without a resolved scene: as requested, below).
    case Param::Eye: return rs ? triple(rs->camera.eye) : nlohmann::json();
    case Param::Target: return rs ? triple(rs->camera.target) : nlohmann::json();
    case Param::Up: return rs ? triple(rs->camera.up) : nlohmann::json();
    case Param::Fov: return rs ? nlohmann::json(exactDegrees(rs->camera.yfov)) : nlohmann::json();
    case Param::LightDir: return rs ? triple(-rs->scene.light.direction) : nlohmann::json();
    case Param::AoTexelDepth: return !s.ssao.tangentPlaneDepth;
    case Param::DisableLevel: {
      nlohmann::json levels = nlohmann::json::array();
      for (int l = 1; l < kLevelCount; ++l)
        if (!s.levels[static_cast<size_t>(l)].enabled) levels.push_back(l);
      return levels;
    }
    case Param::BlendMaterials: return fo.blendMaterials;
    case Param::Gaze:
      return s.foveation.gaze ? nlohmann::json(std::to_string(s.foveation.gazeX) + "," + std::to_string(s.foveation.gazeY))
                              : nlohmann::json();
    case Param::PrevFrame: return fo.prevFrame.empty() ? nlohmann::json() : nlohmann::json(fo.prevFrame);
    case Param::Pan: return s.foveation.panned ? nlohmann::json(s.foveation.pan) : nlohmann::json();
    case Param::FlipUp: return fo.flipUp || fo.noFlipUp ? nlohmann::json(fo.flipUp) : nlohmann::json();
    default: throw MrrError("internal: " + optionName(param) + " is marked for frame files but has no value there");
  }
}

}  // namespace

nlohmann::json FrameOptions::frame(const ResolvedScene& rs, const Settings& s) const { return frame(&rs, s); }

nlohmann::json FrameOptions::frame(const ResolvedScene* rs, const Settings& s) const {
  nlohmann::json j = {{"mrr_frame", 1}};
  for (const FrameParamInfo& p : frameParams()) {
    if (!p.frameFile) continue;
    nlohmann::json v = frameValue(p.param, *this, rs, s);
    if (!v.is_null()) j[std::string(p.key)] = std::move(v);
  }
  return j;
}

void FrameOptions::checkPath(bool bothAllowed) const {
  gpu::parseGpuTiming(gpuTiming);  // validates the name
  if (bothAllowed && path == "both") return;
  require(path == "cpu" || path == "gpu",
          optionName(Param::Path) + " " + path + ": unknown path (expected cpu or gpu" + (bothAllowed ? ", or both" : "") + ")");
}

}  // namespace mrr
