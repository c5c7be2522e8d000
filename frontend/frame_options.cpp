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

// The FrameOptions field a row of the frame-parameter table sets.
using Field = std::variant<std::string FrameOptions::*, int FrameOptions::*, std::optional<int> FrameOptions::*,
                           std::optional<float> FrameOptions::*, std::optional<double> FrameOptions::*,
                           bool FrameOptions::*, std::vector<int> FrameOptions::*, std::vector<float> FrameOptions::*>;

Field bindField(Param param) {
  using F = FrameOptions;
  switch (param) {
    case Param::Scene: return &F::scene;
    case Param::Effect: return &F::effect;
    case Param::Method: return &F::mode;
    case Param::NeverSlower: return &F::neverSlower;
    case Param::CostModel: return &F::costModelFile;
    case Param::Path: return &F::path;
    case Param::GlDevice: return &F::glDevice;
    case Param::GpuTiming: return &F::gpuTiming;
    case Param::Size: return &F::size;
    case Param::Samples: return &F::samples;
    case Param::Threads: return &F::threads;
    case Param::Seed: return &F::seed;
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
    case Param::AoRadius: return &F::aoRadius;
    case Param::AoBias: return &F::aoBias;
    case Param::ShadowMapSize: return &F::shadowMapSize;
    case Param::LightAngle: return &F::lightAngle;
    case Param::GiRadius: return &F::giRadius;
    case Param::AoTexelDepth: return &F::texelDepth;
    case Param::TauN: return &F::tauN;
    case Param::TauZ: return &F::tauZ;
    case Param::DisableLevel: return &F::disabledLevels;
    case Param::Sigma2: return &F::sigma2;
    case Param::Weights: return &F::weights;
    case Param::EffectCap: return &F::effectCap;
    case Param::EffectFirstLevel: return &F::effectFirstLevel;
    case Param::EffectScale: return &F::effectScale;
    case Param::EffectPosterior: return &F::effectPosterior;
    case Param::EffectPosteriorFinest: return &F::effectPosteriorFinest;
    case Param::Ppd: return &F::ppd;
    case Param::Gaze: return &F::gaze;
    case Param::Foveate: return &F::foveate;
    case Param::PrevFrame: return &F::prevFrame;
    case Param::MemoryLimit: return &F::memoryLimitGiB;
    case Param::Quiet: return &F::quiet;
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
    std::visit(
        [&](auto member) {
          auto& field = this->*member;
          using T = std::decay_t<decltype(field)>;
          if constexpr (std::is_same_v<T, bool>) {
            app.add_flag(names, field, paramHelp(p.param));
          } else if constexpr (std::is_same_v<T, std::string>) {
            // The front end's own default (the member's initial value) is the one shown.
            app.add_option(names, field, paramHelp(p.param, field));
          } else {
            CLI::Option* o = app.add_option(names, field, paramHelp(p.param));
            if constexpr (std::is_same_v<T, std::vector<float>>) o->delimiter(',');  // "v0,v1,v2,v3"
            if constexpr (std::is_same_v<T, std::optional<int>> || std::is_same_v<T, std::optional<float>>)
              o->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
          }
        },
        bindField(p.param));
  }
}

Settings FrameOptions::settings() const {
  Settings s = defaultSettings(parseEffect(effect));
  s.mode = parseMode(mode);
  require(neverSlower.empty() || neverSlower == "on" || neverSlower == "off",
          optionName(Param::NeverSlower) + " " + neverSlower + ": expected on or off");
  s.neverSlower = neverSlower.empty() ? neverSlowerDefault : neverSlower == "on";
  const auto [w, h] = parseSize(size);
  s.width = w;
  s.height = h;
  if (samples) s.setSamples(*samples);
  require(seed >= 0 && seed < (1 << 30), optionName(Param::Seed) + " " + std::to_string(seed) + ": must be in " + paramRange(Param::Seed));
  s.seed = static_cast<uint32_t>(seed);
  require(coarseGBuffer == "subsample" || coarseGBuffer == "render",
          optionName(Param::CoarseGbuffer) + " " + coarseGBuffer + ": expected subsample or render");
  s.renderCoarseGBuffer = coarseGBuffer == "render";
  if (aoRadius) s.ssao.radius = *aoRadius;
  if (aoBias) s.ssao.biasFraction = *aoBias;
  if (giRadius) s.ssgi.radius = *giRadius;
  if (shadowMapSize) s.ssm.shadowMapSize = *shadowMapSize;
  if (lightAngle) s.ssm.lightAngle = *lightAngle;
  s.ssao.tangentPlaneDepth = !texelDepth;
  if (effectCap) s.effectMask.cap = *effectCap;
  if (effectFirstLevel) s.effectMask.firstLevel = *effectFirstLevel;
  if (effectScale) s.effectMask.scale = *effectScale;
  if (effectPosterior) s.effectMask.posterior = *effectPosterior;
  if (effectPosteriorFinest) s.effectMask.posteriorFinest = *effectPosteriorFinest;
  if (tauN) s.edges.normalThreshold = *tauN;
  if (tauZ) s.edges.depthThreshold = *tauZ;
  // One number per level, as CLI11 split them at the commas.
  const auto perLevel = [](const std::vector<float>& values, Param param, const char* what, auto valid, auto set) {
    if (values.empty()) return;
    std::string text;
    for (float v : values) text += (text.empty() ? "" : ",") + exactFloat(v);
    require(values.size() == kLevelCount, optionName(param) + " " + text + ": expected " + std::to_string(kLevelCount) +
                                              " numbers, one per level, e.g. 1,1,1,1");
    for (size_t l = 0; l < values.size(); ++l) {
      require(std::isfinite(values[l]) && valid(values[l]),
              optionName(param) + " " + text + ": level " + std::to_string(l) + "'s " + what);
      set(l, values[l]);
    }
  };
  perLevel(sigma2, Param::Sigma2, "variance must be in [0, 64]", [](float v) { return v >= 0.0f && v <= 64.0f; },
           [&](size_t l, float v) { s.levels[l].sigma2 = v; });
  perLevel(weights, Param::Weights, "weight must be >= 0", [](float v) { return v >= 0.0f; },
           [&](size_t l, float v) { s.levels[l].weight = v; });
  // SPEC §13: viewing conditions, the gaze and the previous frame.
  if (ppd) s.foveation.ppd = *ppd;
  if (!gaze.empty()) {
    int gx = 0, gy = 0;
    char comma = 0, rest = 0;
    require(std::sscanf(gaze.c_str(), "%d%c%d%c", &gx, &comma, &gy, &rest) == 3 && comma == ',',
            optionName(Param::Gaze) + " " + gaze + ": expected X,Y, a full-res pixel (whole numbers)");
    s.foveation.gaze = true;
    s.foveation.gazeX = gx;
    s.foveation.gazeY = gy;
  }
  require(foveate == "on" || foveate == "off", optionName(Param::Foveate) + " " + foveate + ": expected on or off");
  s.foveation.foveate = foveate == "on";
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
nlohmann::json frameValue(Param param, const FrameOptions& fo, const ResolvedScene& rs, const Settings& s) {
  auto triple = [](const glm::vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
  auto perLevel = [&](auto get) {
    std::string text;
    for (size_t l = 0; l < s.levels.size(); ++l) {
      if (l) text += ',';
      text += exactFloat(get(s.levels[l]));
    }
    return text;
  };
  switch (param) {
    case Param::Scene: return fo.scene;
    case Param::Effect: return toString(s.effect);
    case Param::Method: return toString(s.mode);
    case Param::Size: return std::to_string(s.width) + "x" + std::to_string(s.height);
    case Param::Samples: return s.samples();
    case Param::Seed: return s.seed == 0 ? nlohmann::json() : nlohmann::json(s.seed);  // absent: 0, mrr's own
    case Param::CoarseGbuffer: return s.renderCoarseGBuffer ? nlohmann::json("render") : nlohmann::json();  // absent: subsample
    case Param::Eye: return triple(rs.camera.eye);
    case Param::Target: return triple(rs.camera.target);
    case Param::Up: return triple(rs.camera.up);
    case Param::Fov: return exactDegrees(rs.camera.yfov);
    case Param::LightDir: return triple(-rs.scene.light.direction);
    case Param::LightAngle: return s.ssm.lightAngle;
    case Param::ShadowMapSize: return s.ssm.shadowMapSize;
    case Param::AoRadius: return s.ssao.radius;
    case Param::AoBias: return s.ssao.biasFraction;
    case Param::GiRadius: return s.ssgi.radius;
    case Param::AoTexelDepth: return !s.ssao.tangentPlaneDepth;
    case Param::TauN: return s.edges.normalThreshold;
    case Param::TauZ: return s.edges.depthThreshold;
    case Param::Sigma2: return perLevel([](const LevelSettings& l) { return l.sigma2; });
    case Param::Weights: return perLevel([](const LevelSettings& l) { return l.weight; });
    case Param::DisableLevel: {
      nlohmann::json levels = nlohmann::json::array();
      for (int l = 1; l < kLevelCount; ++l)
        if (!s.levels[static_cast<size_t>(l)].enabled) levels.push_back(l);
      return levels;
    }
    case Param::NeverSlower: return s.neverSlower ? "on" : "off";
    case Param::BlendMaterials: return fo.blendMaterials;
    // mrr-effect's widening: in the files of that method only
    case Param::EffectCap: return s.mode == Mode::MrrEffect ? nlohmann::json(s.effectMask.cap) : nlohmann::json();
    case Param::EffectFirstLevel:
      return s.mode == Mode::MrrEffect ? nlohmann::json(s.effectMask.firstLevel) : nlohmann::json();
    case Param::EffectScale: return s.mode == Mode::MrrEffect ? nlohmann::json(s.effectMask.scale) : nlohmann::json();
    case Param::EffectPosterior:
      return s.mode == Mode::MrrEffect ? nlohmann::json(s.effectMask.posterior) : nlohmann::json();
    case Param::EffectPosteriorFinest:
      return s.mode == Mode::MrrEffect ? nlohmann::json(s.effectMask.posteriorFinest) : nlohmann::json();
    case Param::Ppd: return s.foveation.ppd;
    case Param::Gaze:
      return s.foveation.gaze ? nlohmann::json(std::to_string(s.foveation.gazeX) + "," + std::to_string(s.foveation.gazeY))
                              : nlohmann::json();
    case Param::Foveate: return s.foveation.gaze ? nlohmann::json(s.foveation.foveate ? "on" : "off") : nlohmann::json();
    case Param::PrevFrame: return fo.prevFrame.empty() ? nlohmann::json() : nlohmann::json(fo.prevFrame);
    case Param::FlipUp: return fo.flipUp || fo.noFlipUp ? nlohmann::json(fo.flipUp) : nlohmann::json();
    default: throw MrrError("internal: " + optionName(param) + " is marked for frame files but has no value there");
  }
}

}  // namespace

nlohmann::json FrameOptions::frame(const ResolvedScene& rs, const Settings& s) const {
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
