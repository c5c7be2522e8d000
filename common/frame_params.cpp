#include "common/frame_params.h"

#include <array>
#include <cstdio>

#include "common/error.h"
#include "common/params.h"

namespace mrr {

namespace {

using K = ParamKind;
constexpr bool kFile = true, kNoFile = false, kPage = true, kNoPage = false;

// One row a parameter: Param, key, alias, kind, unit, help, frame file, explore.
const std::vector<FrameParamInfo> kFrameParams = {
    {Param::Scene, "scene", "", K::Text, "",
     "builtin:NAME, a shared scene (cornell, arcade, apartment) or a .gltf/.glb path", kFile, kPage},
    {Param::Effect, "effect", "", K::Text, "", "ssao, ssm (PCSS soft shadows) or ssgi (indirect light)", kFile, kPage},
    {Param::Method, "method", "--mode", K::Text, "",
     "mrr (= multires, the method), full (the reference), or a peer: uniform-1, uniform-2 (one coarse level, "
     "joint bilateral upsampling), tiles (16x16 VRS-style rates)",
     kFile, kPage},
    {Param::NeverSlower, "never_slower", "", K::Text, "",
     "mrr: shade the frame at full res when the cost model predicts no gain: on|off (compare: off by default, it "
     "validates every stage)",
     kFile, kPage},
    {Param::CostModel, "cost_model", "", K::Text, "",
     "the never-slower rule's costs, a JSON written by `mrr bench --calibrate` (default: built in)", kNoFile, kNoPage},
    {Param::Path, "path", "", K::Text, "", "cpu (the oracle) or gpu (the OpenGL 3.3 port, headless EGL); probe: also both",
     kNoFile, kNoPage},
    {Param::GlDevice, "gl_device", "", K::Int, "",
     "gpu: the EGL device index (default: the first that gives GL 3.3 core)", kNoFile, kNoPage},
    {Param::GpuTiming, "gpu_timing", "", K::Text, "",
     "gpu: stage timings by glFinish + wall clock (wall), GL_TIME_ELAPSED queries (query), or auto: wall on "
     "llvmpipe, whose queries are wrong, query elsewhere",
     kNoFile, kNoPage},
    {Param::Size, "size", "", K::Text, "", "WIDTHxHEIGHT", kFile, kPage},
    {Param::Samples, "samples", "", K::Int, "", "samples per pixel (ssm: PCF taps)", kFile, kPage},
    {Param::Threads, "threads", "", K::Int, "", "worker threads (0 = all cores); results are identical for any count",
     kNoFile, kNoPage},
    {Param::Seed, "seed", "", K::Int, "",
     "ssao/ssgi: the sampling seed of the kernel and the per-pixel rotations (0 = mrr's own sampling; another value "
     "draws the same estimator's noise anew, for `compare --noise-aware`)",
     kFile, kNoPage},
    {Param::CoarseGbuffer, "coarse_gbuffer", "", K::Text, "",
     "the coarser levels' G-buffers: subsample (level pixel (x, y) copies full-res pixel (x s + s/2, y s + s/2), "
     "mrr's) or render (one sample at the level pixel's centre ((x + 1/2) s, (y + 1/2) s), the paper's: a ray on "
     "the oracle, rasterised at the level's size on the port); docs/spec.md §1",
     kFile, kNoPage},
    {Param::Camera, "camera", "", K::Int, "", "index into the scene's cameras", kNoFile, kPage},
    {Param::Eye, "eye", "", K::Triple, "", "camera position x,y,z (with --target)", kFile, kPage},
    {Param::Target, "target", "", K::Triple, "", "camera target x,y,z (with --eye)", kFile, kPage},
    {Param::Up, "up", "", K::Triple, "", "camera up x,y,z (with --eye and --target; default 0,1,0)", kFile, kPage},
    {Param::Fov, "fov", "", K::Number, "degrees", "vertical field of view", kFile, kPage},
    {Param::Frame, "frame", "", K::Text, "",
     "a frame file (JSON, as render --frame-out writes it): scene, camera, light, size, effect, samples and every "
     "parameter; options given here win",
     kNoFile, kNoPage},
    {Param::BlendMaterials, "blend_materials", "", K::Text, "",
     "glTF materials with alphaMode BLEND: opaque (drawn as solid) or skip (left out)", kFile, kPage},
    {Param::LightDir, "light_dir", "", K::Triple, "",
     "x,y,z: the direction toward the directional light, world space (default: the scene's light, or for a scene "
     "without one the built-in default)",
     kFile, kPage},
    {Param::FlipUp, "flip_up", "", K::Flag, "", "rotate the scene 180 degrees about X (files authored Y-down)", kFile,
     kPage},
    {Param::NoFlipUp, "no_flip_up", "", K::Flag, "", "do not flip, even where the scene catalogue would", kNoFile,
     kPage},
    {Param::AoRadius, "ao_radius", "", K::Number, "world units", "ssao: the sample radius R (0 = automatic)", kFile,
     kPage},
    {Param::AoBias, "ao_bias", "", K::Number, "a fraction of R",
     "ssao: the depth bias; an occluder counts when it is in front of the sample by more than this", kFile, kPage},
    {Param::ShadowMapSize, "shadow_map_size", "", K::Int, "texels", "ssm/ssgi: shadow map texels per side", kFile,
     kPage},
    {Param::LightAngle, "light_angle", "", K::Number, "radians", "ssm: the light's angular diameter", kFile, kPage},
    {Param::GiRadius, "gi_radius", "", K::Number, "world units", "ssgi: the sample radius R (0 = automatic)", kFile,
     kPage},
    {Param::AoTexelDepth, "ao_texel_depth", "", K::Flag, "",
     "ssao: compare against the texel-centre depth instead of the tangent plane (the classic test)", kFile, kPage},
    {Param::TauN, "tau_n", "", K::Number, "", "normal-edge threshold on 1 - N.N", kFile, kPage},
    {Param::TauZ, "tau_z", "", K::Number, "", "depth-edge threshold on |second difference of 1/z| / (1/z)", kFile,
     kPage},
    {Param::DisableLevel, "disable_level", "", K::Levels, "", "disable level 1, 2 or 3 (repeatable)", kFile, kPage},
    {Param::Sigma2, "sigma2", "", K::PerLevel, "level pixels",
     "the mask blur's variance per level, s0,s1,s2,s3, each in [0, 64]", kFile, kPage},
    {Param::Weights, "weights", "", K::PerLevel, "",
     "the blend weight w per level, w0,w1,w2,w3, each >= 0: alpha = min(a w, 1)", kFile, kPage},
    {Param::EffectCap, "effect_cap", "", K::Int, "level pixels",
     "mrr-effect: the widest a level's edge mask is widened by the effect's footprint (docs/spec.md section 12)",
     kFile, kPage},
    {Param::EffectFirstLevel, "effect_first_level", "", K::Int, "",
     "mrr-effect: the finest level widened; finer ones keep mrr's masks", kFile, kPage},
    {Param::EffectScale, "effect_scale", "", K::Number, "",
     "mrr-effect: the footprint's multiplier (0: mrr's masks exactly)", kFile, kPage},
    {Param::EffectPosterior, "effect_posterior", "", K::Number, "the effect's units",
     "mrr-effect: the a-posteriori threshold tau: a level pixel is refined where its next coarser level's "
     "result varies by more than tau over 3x3 (0: off; docs/spec.md section 12.2)",
     kFile, kPage},
    {Param::EffectPosteriorFinest, "effect_posterior_finest", "", K::Int, "",
     "mrr-effect: the finest level the a-posteriori term refines", kFile, kPage},
    {Param::EffectOnly, "effect_only", "", K::Flag, "",
     "mrr-effect: the ablation's effect-only arm: each level keeps only the pixels the footprint's widening adds, "
     "none of the edges' own (docs/spec.md section 12.3)",
     kFile, kPage},
    {Param::Ppd, "ppd", "", K::Number, "pixels per degree",
     "viewing conditions: pixels per degree of visual angle (67.02: a 0.7 m wide 4K display seen from 0.7 m); "
     "sets the eccentricity of --gaze and the reports' FLIP",
     kFile, kPage},
    {Param::Gaze, "gaze", "", K::Text, "full-res pixel",
     "X,Y: the pixel the eye looks at; the periphery may use coarser levels (foveation, docs/spec.md section 13)",
     kFile, kPage},
    {Param::Foveate, "foveate", "", K::Text, "",
     "with --gaze: on coarsens the periphery; off only measures (eccentricity, the report's rings), the baseline",
     kFile, kPage},
    {Param::PrevFrame, "prev_frame", "", K::Text, "",
     "the previous frame, a frame file as render --frame-out writes it (same scene and size): pixels that move "
     "on screen may use coarser levels (docs/spec.md section 13)",
     kFile, kNoPage},
    {Param::Pan, "pan", "", K::Number, "world units",
     "motion without a file: the previous frame's camera is this one moved X units along its own right axis "
     "the other way (the camera panned X to the right since; negative: to the left); pixels that move on screen "
     "may use coarser levels (docs/spec.md section 13); 0 = off; not with --prev-frame",
     kFile, kPage},
    {Param::MemoryLimit, "memory_limit", "", K::Number, "GiB",
     "what the run may plan to use; unset: MRR_MEMORY_LIMIT, else 3/4 of physical memory", kNoFile, kNoPage},
    {Param::Quiet, "quiet", "-q", K::Flag, "", "no progress lines on stderr", kNoFile, kNoPage},
};

bool rowsInEnumOrder() {
  for (size_t i = 0; i < kFrameParams.size(); ++i)
    if (static_cast<size_t>(kFrameParams[i].param) != i) return false;
  return kFrameParams.back().param == Param::Quiet;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// "v0,v1,v2,v3" of one effect's per-level defaults.
template <typename Get>
std::string perLevelText(Effect effect, Get get) {
  const Settings s = defaultSettings(effect);
  std::string text;
  for (size_t l = 0; l < s.levels.size(); ++l) {
    if (l) text += ',';
    text += number(get(s.levels[l]));
  }
  return text;
}

// The algorithm's default, from defaultSettings; per effect where Table 1 differs by effect.
std::string settingsDefault(Param param) {
  const Settings s = defaultSettings(Effect::Ssao);
  const std::array effects = {Effect::Ssao, Effect::Ssm, Effect::Ssgi};
  auto perEffect = [&](auto text) {
    std::string out;
    for (Effect e : effects) {
      if (!out.empty()) out += ", ";
      out += toString(e) + " " + text(e);
    }
    return out;
  };
  switch (param) {
    case Param::Samples: return perEffect([](Effect e) { return std::to_string(defaultSettings(e).samples()); });
    case Param::ShadowMapSize: return std::to_string(s.ssm.shadowMapSize);
    case Param::LightAngle: return number(s.ssm.lightAngle);
    case Param::TauN: return number(s.edges.normalThreshold);
    case Param::TauZ: return number(s.edges.depthThreshold);
    case Param::AoRadius:
      return number(s.ssao.radius) + ": " + number(100.0 * SsaoSettings::kAutoRadiusFraction) + "% of the framed size (the view's height at its median surface depth)";
    case Param::AoBias: return number(s.ssao.biasFraction);
    case Param::GiRadius:
      return number(s.ssgi.radius) + ": " + number(100.0 * SsgiSettings::kAutoRadiusFraction) + "% of the framed size";
    case Param::NeverSlower: return s.neverSlower ? "on" : "off";
    case Param::EffectCap: return std::to_string(s.effectMask.cap);
    case Param::EffectFirstLevel: return std::to_string(s.effectMask.firstLevel);
    case Param::EffectScale: return number(s.effectMask.scale);
    case Param::EffectPosterior: return number(s.effectMask.posterior);
    case Param::EffectPosteriorFinest: return std::to_string(s.effectMask.posteriorFinest);
    case Param::Ppd: return number(s.foveation.ppd);
    case Param::Sigma2:
      return "the paper's Table 1: " + perEffect([](Effect e) { return perLevelText(e, [](const LevelSettings& l) { return l.sigma2; }); });
    case Param::Weights:
      return "the paper's Table 1: " + perEffect([](Effect e) { return perLevelText(e, [](const LevelSettings& l) { return l.weight; }); });
    default: return "";
  }
}

}  // namespace

const std::vector<FrameParamInfo>& frameParams() {
  static const bool ordered = rowsInEnumOrder();
  require(ordered, "internal: kFrameParams must list every Param in enum order");
  return kFrameParams;
}

const FrameParamInfo& paramInfo(Param param) { return frameParams()[static_cast<size_t>(param)]; }

std::string optionName(Param param) {
  std::string option = "--" + std::string(paramInfo(param).key);
  for (char& c : option)
    if (c == '_') c = '-';
  return option;
}

const FrameParamInfo* findParam(std::string_view name) {
  for (const FrameParamInfo& p : frameParams()) {
    if (name == p.key || name == optionName(p.param)) return &p;
    for (std::string_view rest = p.alias; !rest.empty();) {
      const size_t comma = rest.find(',');
      if (name == rest.substr(0, comma)) return &p;
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
    }
  }
  return nullptr;
}

std::string paramRange(Param param) {
  switch (param) {
    case Param::Size: return "each side in [1, " + std::to_string(kMaxImageSize) + "]";
    case Param::Samples:
      return "ssao [1, " + std::to_string(kMaxSsaoSamples) + "], ssm a square n*n up to " +
             std::to_string(kMaxSsmSamples) + ", ssgi [1, " + std::to_string(kMaxSsgiSamples) + "]";
    case Param::ShadowMapSize: return "[16, " + std::to_string(kMaxShadowMapSize) + "]";
    case Param::LightAngle: return "(0, 0.5]";
    case Param::EffectCap: return "[0, 64]";
    case Param::EffectFirstLevel: return "[0, 3]";
    case Param::EffectScale: return "[0, 16]";
    case Param::EffectPosterior: return "[0, 100]";
    case Param::EffectPosteriorFinest: return "[0, 3]";
    case Param::Ppd: return "> 0";
    case Param::Pan: return "[-1e6, 1e6]";
    case Param::TauN: return "[0, 2]";
    case Param::AoBias: return "[0, 1]";
    case Param::TauZ:
    case Param::AoRadius:
    case Param::GiRadius: return ">= 0";
    case Param::Threads: return "[0, 1024]";
    case Param::Seed: return "[0, 1073741823]";
    default: return "";
  }
}

std::string paramHelp(Param param, const std::string& frontEndDefault) {
  const FrameParamInfo& p = paramInfo(param);
  std::string help(p.help);
  if (!p.unit.empty()) help += ", " + std::string(p.unit);
  if (const std::string range = paramRange(param); !range.empty()) help += "; range " + range;
  const std::string fromSettings = settingsDefault(param);
  const std::string shown = fromSettings.empty() ? frontEndDefault : fromSettings;
  if (!shown.empty()) help += "; default " + shown;
  return help;
}

}  // namespace mrr
