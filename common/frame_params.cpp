#include "common/frame_params.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "common/error.h"
#include "common/params.h"

namespace mrr {

namespace {

using K = ParamKind;
constexpr bool kFile = true, kNoFile = false, kPage = true, kNoPage = false;
constexpr double kUnbounded = std::numeric_limits<double>::infinity();
constexpr ParamRange closed(double lo, double hi) { return {lo, hi, false, false}; }
constexpr ParamRange atLeast(double lo) { return {lo, kUnbounded, false, true}; }  // finite, >= lo
constexpr ParamRange above(double lo) { return {lo, kUnbounded, true, true}; }     // finite, > lo
constexpr ParamRange openClosed(double lo, double hi) { return {lo, hi, true, false}; }
static_assert(sizeof(PerLevelField::values) / sizeof(float*) == kLevelCount);

// The Settings field of a row, where it sets one.
#define MRR_FIELD(expr) [](Settings& s) -> SettingField { return &(expr); }
SettingField sigma2Field(Settings& s) {
  return PerLevelField{{&s.levels[0].sigma2, &s.levels[1].sigma2, &s.levels[2].sigma2, &s.levels[3].sigma2}};
}
SettingField weightsField(Settings& s) {
  return PerLevelField{{&s.levels[0].weight, &s.levels[1].weight, &s.levels[2].weight, &s.levels[3].weight}};
}

// One row a parameter: Param, key, alias, kind, unit, help, frame file, explore.
const std::vector<FrameParamInfo> kFrameParams = {
    {Param::Scene, "scene", "", K::Text, "",
     "builtin:NAME, a shared scene (cornell, arcade, apartment) or a .gltf/.glb path", kFile, kPage},
    {Param::Effect, "effect", "", K::Text, "", "ssao, ssm (PCSS soft shadows) or ssgi (indirect light)", kFile, kPage},
    {Param::Method, "method", "--mode", K::Text, "", "the method, a row of the method table (mrr methods)", kFile,
     kPage},
    {Param::NeverSlower, "never_slower", "", K::Switch, "",
     "mrr: shade the frame at full res when the cost model predicts no gain: on|off (compare: off by default, it "
     "validates every stage)",
     kFile, kPage, {}, MRR_FIELD(s.neverSlower)},
    {Param::CostModel, "cost_model", "", K::Text, "",
     "the never-slower rule's costs, a JSON written by `mrr bench --calibrate` (default: built in)", kNoFile, kNoPage},
    {Param::Path, "path", "", K::Text, "", "cpu (the oracle) or gpu (the OpenGL 3.3 port, headless EGL); probe: also both",
     kNoFile, kNoPage},
    {Param::GlDevice, "gl_device", "", K::Int, "",
     "gpu: the EGL device index (default: the first that gives GL 3.3 core)", kNoFile, kNoPage},
    {Param::GpuTiming, "gpu_timing", "", K::Text, "",
     "gpu: stage timings by glFinish + wall clock (wall), GL_TIME_ELAPSED queries (query), auto: wall on "
     "llvmpipe, whose queries are wrong, query elsewhere, or passes: wall and each draw timed alone too, the "
     "report's passes (a diagnostic: its waits slow the frame)",
     kNoFile, kNoPage},
    {Param::Size, "size", "", K::Text, "", "WIDTHxHEIGHT", kFile, kPage},
    {Param::Samples, "samples", "", K::Int, "", "samples per pixel (ssm: PCF taps)", kFile, kPage},
    {Param::Threads, "threads", "", K::Int, "", "worker threads (0 = all cores); results are identical for any count",
     kNoFile, kNoPage, closed(0, 1024)},
    {Param::Seed, "seed", "", K::Int, "",
     "ssao/ssgi: the sampling seed of the kernel and the per-pixel rotations (0 = mrr's own sampling; another value "
     "draws the same estimator's noise anew, for `compare --noise-aware`)",
     kFile, kNoPage, closed(0, 1073741823), MRR_FIELD(s.seed)},
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
     kPage, atLeast(0), MRR_FIELD(s.ssao.radius)},
    {Param::AoBias, "ao_bias", "", K::Number, "a fraction of R",
     "ssao: the depth bias; an occluder counts when it is in front of the sample by more than this", kFile, kPage, closed(0, 1), MRR_FIELD(s.ssao.biasFraction)},
    {Param::ShadowMapSize, "shadow_map_size", "", K::Int, "texels", "ssm/ssgi: shadow map texels per side", kFile,
     kPage, closed(16, 8192), MRR_FIELD(s.ssm.shadowMapSize)},
    {Param::LightAngle, "light_angle", "", K::Number, "radians", "ssm: the light's angular diameter", kFile, kPage, openClosed(0, 0.5), MRR_FIELD(s.ssm.lightAngle)},
    {Param::GiRadius, "gi_radius", "", K::Number, "world units", "ssgi: the sample radius R (0 = automatic)", kFile,
     kPage, atLeast(0), MRR_FIELD(s.ssgi.radius)},
    {Param::AoTexelDepth, "ao_texel_depth", "", K::Flag, "",
     "ssao: compare against the texel-centre depth instead of the tangent plane (the classic test)", kFile, kPage},
    {Param::TauN, "tau_n", "", K::Number, "", "normal-edge threshold on 1 - N.N", kFile, kPage, closed(0, 2), MRR_FIELD(s.edges.normalThreshold)},
    {Param::TauZ, "tau_z", "", K::Number, "", "depth-edge threshold on |second difference of 1/z| / (1/z)", kFile,
     kPage, atLeast(0), MRR_FIELD(s.edges.depthThreshold)},
    {Param::DisableLevel, "disable_level", "", K::Levels, "", "disable level 1, 2 or 3 (repeatable)", kFile, kPage},
    {Param::Sigma2, "sigma2", "", K::PerLevel, "level pixels",
     "the mask blur's variance per level, s0,s1,s2,s3, each in [0, 64]", kFile, kPage, closed(0, 64), sigma2Field},
    {Param::Weights, "weights", "", K::PerLevel, "",
     "the blend weight w per level, w0,w1,w2,w3, each >= 0: alpha = min(a w, 1)", kFile, kPage, atLeast(0), weightsField},
    {Param::EffectCap, "effect_cap", "", K::Int, "level pixels",
     "mrr-effect: the widest a level's edge mask is widened by the effect's footprint (docs/spec.md section 12)",
     kFile, kPage, closed(0, 64), MRR_FIELD(s.effectMask.cap)},
    {Param::EffectFirstLevel, "effect_first_level", "", K::Int, "",
     "mrr-effect: the finest level widened; finer ones keep mrr's masks", kFile, kPage, closed(0, 3), MRR_FIELD(s.effectMask.firstLevel)},
    {Param::EffectScale, "effect_scale", "", K::Number, "",
     "mrr-effect: the footprint's multiplier (0: mrr's masks exactly)", kFile, kPage, closed(0, 16), MRR_FIELD(s.effectMask.scale)},
    {Param::EffectPosterior, "effect_posterior", "", K::Number, "the effect's units",
     "mrr-effect: the a-posteriori threshold tau: a level pixel is refined where its next coarser level's "
     "result varies by more than tau over 3x3 (0: off; docs/spec.md section 12.2)",
     kFile, kPage, closed(0, 100), MRR_FIELD(s.effectMask.posterior)},
    {Param::EffectPosteriorFinest, "effect_posterior_finest", "", K::Int, "",
     "mrr-effect: the finest level the a-posteriori term refines", kFile, kPage, closed(0, 3), MRR_FIELD(s.effectMask.posteriorFinest)},
    {Param::EffectOnly, "effect_only", "", K::Flag, "",
     "mrr-effect: the ablation's effect-only arm: each level keeps only the pixels the footprint's widening adds, "
     "none of the edges' own (docs/spec.md section 12.3)",
     kFile, kPage, {}, MRR_FIELD(s.effectMask.effectOnly)},
    {Param::EffectBudget, "effect_budget", "", K::Number, "share of full's predicted time",
     "mrr-effect: the a-posteriori term's budget: it refines the candidates with the most variation per predicted "
     "nanosecond until the method's predicted rest of frame reaches this share of full's (0: off, tau alone "
     "decides; docs/spec.md section 12.4)",
     kFile, kPage, closed(0, 1), MRR_FIELD(s.effectMask.budget)},
    {Param::EffectTemporal, "effect_temporal", "", K::Number, "",
     "mrr-effect: the temporal term's lambda: the share of the previous frame's result a pixel served by the "
     "coarser levels keeps where reprojection finds the same surface (0: off; with a previous frame only: "
     "--prev-frame, --pan, bench camera paths; docs/spec.md section 14)",
     kFile, kPage, {0.0, 1.0, false, true}, MRR_FIELD(s.effectMask.temporal)},
    {Param::EffectHysteresis, "effect_hysteresis", "", K::Number, "",
     "mrr-effect: the a-posteriori marks' hysteresis h: a pixel the previous frame refined stays refined while its "
     "variation stays above (1 - h) of what a new mark needs (0: off; docs/spec.md section 14.2)",
     kFile, kPage, {0.0, 1.0, false, true}, MRR_FIELD(s.effectMask.hysteresis)},
    {Param::EffectTrim, "effect_trim", "", K::Switch, "",
     "mrr-effect: shade a level > 0 only where the blend reads it: its pixels that are bilinear taps of a full-res "
     "pixel no finer level covers with alpha = 1 (a priori), and for SSAO its blur's 5x5 around them: on|off "
     "(docs/spec.md section 12.5)",
     kFile, kPage, {}, MRR_FIELD(s.effectMask.trim)},
    {Param::TilesTemporal, "tiles_temporal", "", K::Number, "",
     "tiles: docs/spec.md section 14's temporal term with this lambda, as mrr-effect's --effect-temporal, for "
     "comparison (0: off, tiles as it is)",
     kFile, kPage, {0.0, 1.0, false, true}, MRR_FIELD(s.tilesTemporal)},
    {Param::Ppd, "ppd", "", K::Number, "pixels per degree",
     "viewing conditions: pixels per degree of visual angle (67.02: a 0.7 m wide 4K display seen from 0.7 m); "
     "sets the eccentricity of --gaze and the reports' FLIP",
     kFile, kPage, above(0), MRR_FIELD(s.foveation.ppd)},
    {Param::Gaze, "gaze", "", K::Text, "full-res pixel",
     "X,Y: the pixel the eye looks at; the periphery may use coarser levels (foveation, docs/spec.md section 13)",
     kFile, kPage},
    {Param::Foveate, "foveate", "", K::Switch, "",
     "with --gaze: on coarsens the periphery; off only measures (eccentricity, the report's rings), the baseline",
     kFile, kPage, {}, MRR_FIELD(s.foveation.foveate)},
    {Param::PrevFrame, "prev_frame", "", K::Text, "",
     "the previous frame, a frame file as render --frame-out writes it (same scene and size): pixels that move "
     "on screen may use coarser levels (docs/spec.md section 13)",
     kFile, kNoPage},
    {Param::Pan, "pan", "", K::Number, "world units",
     "motion without a file: the previous frame's camera is this one moved X units along its own right axis "
     "the other way (the camera panned X to the right since; negative: to the left); pixels that move on screen "
     "may use coarser levels (docs/spec.md section 13); 0 = off; not with --prev-frame",
     kFile, kPage, closed(-1e6, 1e6)},
    {Param::MemoryLimit, "memory_limit", "", K::Number, "GiB",
     "what the run may plan to use; unset: MRR_MEMORY_LIMIT, else 3/4 of physical memory", kNoFile, kNoPage},
    {Param::Quiet, "quiet", "-q", K::Flag, "", "no progress lines on stderr", kNoFile, kNoPage},
};

bool paramRowsInEnumOrder() {
  for (size_t i = 0; i < kFrameParams.size(); ++i)
    if (static_cast<size_t>(kFrameParams[i].param) != i) return false;
  return kFrameParams.back().param == Param::Quiet;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
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
    case Param::AoRadius:
      return number(s.ssao.radius) + ": " + number(100.0 * SsaoSettings::kAutoRadiusFraction) + "% of the framed size (the view's height at its median surface depth)";
    case Param::GiRadius:
      return number(s.ssgi.radius) + ": " + number(100.0 * SsgiSettings::kAutoRadiusFraction) + "% of the framed size";
    case Param::Sigma2:
    case Param::Weights:
      return "the paper's Table 1: " + perEffect([param](Effect e) { return paramText(defaultSettings(e), param, false); });
    case Param::EffectOnly:
    case Param::Foveate: return "";  // a flag; on with a gaze
    default: return hasSettingField(param) ? paramText(s, param, false) : "";
  }
}

}  // namespace

const std::vector<FrameParamInfo>& frameParams() {
  static const bool ordered = paramRowsInEnumOrder();
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

std::string exactFloat(float v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
  return text;
}

std::string ParamRange::text() const {
  if (!any()) return "";
  // Whole numbers in full ("1073741823"), a large power of ten as one ("1e6"), others as %g.
  const auto num = [](double v) {
    const double a = std::fabs(v);
    if (a >= 1e6 && std::pow(10.0, std::round(std::log10(a))) == a)
      return std::string(v < 0 ? "-" : "") + "1e" + std::to_string(static_cast<int>(std::round(std::log10(a))));
    if (v == std::round(v) && a < 1e15) return std::to_string(static_cast<long long>(v));
    return number(v);
  };
  if (hi == kUnbounded) return std::string(loOpen ? "> " : ">= ") + num(lo);
  return std::string(loOpen ? "(" : "[") + num(lo) + ", " + num(hi) + (hiOpen ? ")" : "]");
}

std::string paramRange(Param param) {
  switch (param) {  // the compound values, checked where they are resolved
    case Param::Size: return "each side in [1, " + std::to_string(kMaxImageSize) + "]";
    case Param::Samples:
      return "ssao [1, " + std::to_string(kMaxSsaoSamples) + "], ssm a square n*n up to " +
             std::to_string(kMaxSsmSamples) + ", ssgi [1, " + std::to_string(kMaxSsgiSamples) + "]";
    default: return paramInfo(param).range.text();
  }
}

std::string rangeRule(Param param) {
  const ParamRange& r = paramInfo(param).range;
  return r.hi == kUnbounded ? "must be " + r.text() : "must be in " + r.text();
}

bool hasSettingField(Param param) { return paramInfo(param).field != nullptr; }

namespace {

// The field of `param`'s row in `s` (const access through the same accessor).
SettingField fieldOf(Settings& s, Param param) {
  const FrameParamInfo& p = paramInfo(param);
  require(p.field != nullptr, "internal: " + optionName(param) + " sets no Settings field");
  return p.field(s);
}

// A whole number or a real number, the whole text; false otherwise.
bool parseNumber(std::string_view text, bool integer, double& out) {
  const std::string t(text);
  if (t.empty() || std::isspace(static_cast<unsigned char>(t[0]))) return false;
  char* end = nullptr;
  if (integer) {
    const long long v = std::strtoll(t.c_str(), &end, 10);
    out = static_cast<double>(v);
  } else {
    out = std::strtod(t.c_str(), &end);
  }
  return end && *end == '\0';
}

}  // namespace

void setParam(Settings& s, Param param, std::string_view text) {
  const FrameParamInfo& p = paramInfo(param);
  const std::string where = optionName(param) + " " + std::string(text);
  const auto inRange = [&](double v) {
    require(p.range.contains(v) || !p.range.any(), where + ": " + rangeRule(param));
    return v;
  };
  std::visit(
      [&](auto field) {
        using T = std::decay_t<decltype(field)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          throw MrrError("internal: " + optionName(param) + " sets no Settings field");
        } else if constexpr (std::is_same_v<T, bool*>) {
          if (p.kind == ParamKind::Switch) {
            require(text == "on" || text == "off", where + ": expected on or off");
            *field = text == "on";
          } else {
            require(text == "1" || text == "0" || text == "true" || text == "false", where + ": expected 1 or 0");
            *field = text == "1" || text == "true";
          }
        } else if constexpr (std::is_same_v<T, PerLevelField>) {
          std::vector<float> values;
          for (std::string_view rest = text;;) {
            const size_t comma = rest.find(',');
            double v = 0.0;
            require(parseNumber(rest.substr(0, comma), false, v), where + ": expected " + std::to_string(kLevelCount) +
                                                                    " numbers, one per level, e.g. 1,1,1,1");
            values.push_back(static_cast<float>(v));
            if (comma == std::string_view::npos) break;
            rest = rest.substr(comma + 1);
          }
          require(values.size() == kLevelCount,
                  where + ": expected " + std::to_string(kLevelCount) + " numbers, one per level, e.g. 1,1,1,1");
          for (size_t l = 0; l < values.size(); ++l) {
            require(p.range.contains(values[l]), where + ": level " + std::to_string(l) + "'s value " + rangeRule(param));
            *field.values[l] = values[l];
          }
        } else {
          constexpr bool integer = !std::is_same_v<T, float*>;
          double v = 0.0;
          require(parseNumber(text, integer, v), where + (integer ? ": expected a whole number" : ": expected a number"));
          *field = static_cast<std::remove_pointer_t<T>>(inRange(v));
        }
      },
      fieldOf(s, param));
}

std::string paramText(const Settings& settings, Param param, bool exact) {
  Settings& s = const_cast<Settings&>(settings);  // the accessor reads through the same pointer
  const FrameParamInfo& p = paramInfo(param);
  return std::visit(
      [&](auto field) -> std::string {
        using T = std::decay_t<decltype(field)>;
        if constexpr (std::is_same_v<T, std::monostate>) {
          return "";
        } else if constexpr (std::is_same_v<T, bool*>) {
          if (p.kind == ParamKind::Switch) return *field ? "on" : "off";
          return *field ? "1" : "0";
        } else if constexpr (std::is_same_v<T, PerLevelField>) {
          std::string text;
          for (size_t l = 0; l < kLevelCount; ++l)
            text += (l ? "," : "") + (exact ? exactFloat(*field.values[l]) : number(*field.values[l]));
          return text;
        } else if constexpr (std::is_same_v<T, float*>) {
          return exact ? exactFloat(*field) : number(*field);
        } else {
          return std::to_string(*field);
        }
      },
      fieldOf(s, param));
}

void checkParamRanges(const Settings& settings) {
  Settings& s = const_cast<Settings&>(settings);
  for (const FrameParamInfo& p : frameParams()) {
    if (!p.field || !p.range.any()) continue;
    std::visit(
        [&](auto field) {
          using T = std::decay_t<decltype(field)>;
          if constexpr (std::is_same_v<T, PerLevelField>) {
            for (size_t l = 0; l < kLevelCount; ++l)
              require(p.range.contains(*field.values[l]), optionName(p.param) + ": level " + std::to_string(l) +
                                                               "'s value " + exactFloat(*field.values[l]) + " " +
                                                               rangeRule(p.param));
          } else if constexpr (std::is_same_v<T, int*> || std::is_same_v<T, float*> || std::is_same_v<T, uint32_t*>) {
            const double v = static_cast<double>(*field);
            require(p.range.contains(v), optionName(p.param) + " " +
                                             (std::is_same_v<T, float*> ? exactFloat(static_cast<float>(v)) : number(v)) +
                                             ": " + rangeRule(p.param));
          }
        },
        p.field(s));
  }
}

std::string paramHelp(Param param, const std::string& frontEndDefault) {
  const FrameParamInfo& p = paramInfo(param);
  std::string help(p.help);
  if (param == Param::Method) {  // every row of the method table, with what it is
    help += ":";
    for (const MethodInfo& m : methods())
      help += " " + std::string(m.name) + (m.aliases.empty() ? "" : " (= " + std::string(m.aliases) + ")") + " (" +
              std::string(m.help) + ");";
    help.pop_back();
  }
  if (!p.unit.empty()) help += ", " + std::string(p.unit);
  if (const std::string range = paramRange(param); !range.empty()) help += "; range " + range;
  const std::string fromSettings = settingsDefault(param);
  const std::string shown = fromSettings.empty() ? frontEndDefault : fromSettings;
  if (!shown.empty()) help += "; default " + shown;
  return help;
}

}  // namespace mrr
