#pragma once
// The frame parameters: one table (issue 33). Every option that says which frame to render is
// one row here, and everything that names one reads it from this table: the command line
// (frontend/frame_options.cpp registers a CLI11 option per row), frame files (their keys and
// how each value becomes a command-line word: frontend/frame_file.cpp), `mrr explore`'s
// allowlist and its page's knobs (/api/info lists the rows), the report's `frame` object, the
// help text, and the messages that name an option (validateSettings). A row's default is typed
// once: the algorithm's numbers in common/params.h (Settings, the paper's Table 1), what the
// front end chooses in FrameOptions' member initialisers; the help shows either, generated.
//
// Adding a parameter: a Param, its row in kFrameParams (common/frame_params.cpp), the field it
// sets (FrameOptions, frontend/frame_options.h: one line of bindField), and its use.
#include <string>
#include <string_view>
#include <vector>

namespace mrr {

enum class Param {
  Scene, Effect, Method, NeverSlower, CostModel, Path, GlDevice, GpuTiming, Size, Samples, Threads,
  Seed, CoarseGbuffer, Camera, Eye, Target, Up, Fov, Frame, BlendMaterials, LightDir, FlipUp, NoFlipUp, AoRadius,
  AoBias, ShadowMapSize, LightAngle, GiRadius, AoTexelDepth, TauN, TauZ, DisableLevel, Sigma2, Weights,
  EffectCap, EffectFirstLevel, EffectScale,  // mrr-effect's widening (issue 35, SPEC §12)
  EffectPosterior, EffectPosteriorFinest,     // mrr-effect's a-posteriori term (SPEC §12.2)
  Ppd, Gaze, Foveate, PrevFrame,  // viewing conditions, foveation and motion (issue 37, SPEC §13)
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
};

struct FrameParamInfo {
  Param param;
  std::string_view key;    // frame-file key and explore parameter; the option is "--" + key, '_' → '-'
  std::string_view alias;  // other option names, CLI11 style ("-q", "--mode"), or ""
  ParamKind kind;
  std::string_view unit;   // "" when the value has none
  std::string_view help;   // what it does; the default and range are added by paramHelp
  bool frameFile;          // written by `render --frame-out`, read back by --frame
  bool explore;            // the explore page may send it (options naming files or the machine stay on the command line)
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

}  // namespace mrr
