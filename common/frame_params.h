#pragma once
// The frame parameters: one table. Every option that says which frame to render is
// one row here, and everything that names one reads it from this table: the command line
// (frontend/frame_options.cpp registers a CLI11 option per row), frame files (their keys and
// how each value becomes a command-line word: frontend/frame_file.cpp), `mrr explore`'s
// allowlist and its page's knobs (/api/info lists the rows), the report's `frame` object, the
// help text, and the messages that name an option (validateSettings). A row's default is typed
// once: the algorithm's numbers in common/params.h (Settings, the paper's Table 1), what the
// front end chooses in FrameOptions' member initialisers; the help shows either, generated.
//
// Adding a parameter (docs/architecture.md, "Adding a parameter"): a Param and its row in
// kFrameParams (common/frame_params.cpp): key, kind, unit, help, range and, where it sets one
// Settings field, that field; then its use. A row with a Settings field needs nothing else: the
// command line, frame files, explore, the bench's variants and the checks of its range all go
// through setParam and checkParamRanges. A row the front end resolves (the scene, the camera,
// files, sizes) also has a FrameOptions field (frontend/frame_options.cpp: bindField).
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace mrr {

struct Settings;  // common/params.h

enum class Param {
  Scene, Effect, Method, NeverSlower, CostModel, Path, GlDevice, GpuTiming, Size, Samples, Threads,
  Seed, CoarseGbuffer, Camera, Eye, Target, Up, Fov, Frame, BlendMaterials, LightDir, FlipUp, NoFlipUp, AoRadius,
  AoBias, ShadowMapSize, LightAngle, GiRadius, AoTexelDepth, TauN, TauZ, DisableLevel, Sigma2, Weights,
  EffectCap, EffectFirstLevel, EffectScale,  // mrr-effect's widening (SPEC §12)
  EffectPosterior, EffectPosteriorFinest,    // mrr-effect's a-posteriori marks (SPEC §12.2)
  EffectOnly,                                // the ablation's effect-only arm (SPEC §12.3)
  EffectBudget,                              // the a-posteriori term's budget in predicted time (SPEC §12.4)
  EffectTemporal, EffectHysteresis,          // the temporal term (SPEC §14)
  EffectTrim,                                // shading only what the blend reads (SPEC §12.5)
  TilesTemporal,                             // the same temporal term for tiles (SPEC §14)
  Ppd, Gaze, Foveate, PrevFrame, Pan,  // viewing conditions, foveation and motion (SPEC §13)
  MemoryLimit, Quiet,
};

// What a value is, on the command line, in a frame file and in a request to `mrr explore`.
enum class ParamKind {
  Text,      // a word ("ssao", "1280x720")
  Int,       // a whole number
  Number,    // a real number
  Triple,    // x,y,z (a JSON array [x, y, z] in a frame file)
  Flag,      // present or not (true/false in a frame file, 1/0 in a request)
  Levels,    // level indices, repeatable (a JSON array in a frame file)
  PerLevel,  // one number per level, "v0,v1,v2,v3"
  Switch,    // on|off
};

// A numeric parameter's documented range, checked from its row (setParam, checkParamRanges).
struct ParamRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool loOpen = false, hiOpen = false;
  bool any() const { return lo != -std::numeric_limits<double>::infinity() || hi != std::numeric_limits<double>::infinity(); }
  bool contains(double v) const {
    return v == v && (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
  }
  std::string text() const;  // "[0, 64]", "(0, 0.5]", ">= 0", "> 0"
};

// The Settings field a row sets, where it sets exactly one (per level: one float per level).
struct PerLevelField {
  float* values[4];  // kLevelCount (static_assert in frame_params.cpp)
};
using SettingField = std::variant<std::monostate, int*, float*, bool*, uint32_t*, PerLevelField>;
using SettingAccessor = SettingField (*)(Settings&);

struct FrameParamInfo {
  Param param;
  std::string_view key;    // frame-file key and explore parameter; the option is "--" + key, '_' → '-'
  std::string_view alias;  // other option names, CLI11 style ("-q", "--mode"), or ""
  ParamKind kind;
  std::string_view unit;   // "" when the value has none
  std::string_view help;   // what it does; the default and range are added by paramHelp
  bool frameFile;          // written by `render --frame-out`, read back by --frame
  bool explore;            // the explore page may send it (options naming files or the machine stay on the command line)
  ParamRange range{};      // its values' range, where numeric (none: not checked here)
  SettingAccessor field{};  // the Settings field it sets, or null: the front end resolves it
};

// Every row, in the order of Param (static_assert in the .cpp) — which is also the order of the
// command line's help and of a frame file's words.
const std::vector<FrameParamInfo>& frameParams();
const FrameParamInfo& paramInfo(Param param);
// "--tau-n": the command-line option of a parameter.
std::string optionName(Param param);
// The row whose key, option or alias is `name` ("tau_n", "--tau-n", "--mode"); nullptr when none.
const FrameParamInfo* findParam(std::string_view name);
// The help line: what it does, its unit and range, and its default as the code holds it (the
// algorithm's from defaultSettings, per effect where the paper's Table 1 differs by effect).
// `frontEndDefault`: the default the front end gives it, already as text ("" : none shown).
std::string paramHelp(Param param, const std::string& frontEndDefault = "");
// The documented range of a numeric parameter ("[0, 2]"), or "" (validateSettings checks it).
std::string paramRange(Param param);
// "must be in [0, 64]" / "must be > 0": what its range asks, for messages.
std::string rangeRule(Param param);

// Sets the Settings field of `param`'s row from text as the command line gives it ("0.2",
// "1,1,2,2", "on"); throws MrrError naming the option, the value and its range. The row must
// have a field (hasSettingField).
void setParam(Settings& settings, Param param, std::string_view text);
bool hasSettingField(Param param);
// The field's value as text, as setParam reads it back ("0.2", "1,1,2,2", "on", "1"); with
// `exact` false floats are shortened for reading ("0.924", not "0.924000025").
std::string paramText(const Settings& settings, Param param, bool exact = true);
// A float as text that reads back to the same bits ("%.9g").
std::string exactFloat(float v);
// Every row with a Settings field and a range: its value within it (validateSettings calls it).
void checkParamRanges(const Settings& settings);

}  // namespace mrr
