#pragma once
// The options that say which frame to render, shared by render, probe, compare and explore:
// the fields the frame-parameter table's rows set (common/frame_params.h: names, kinds, help,
// defaults, which go in frame files and which the explore page may send) and one way from them
// to Settings, the scene request and the cost model.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "common/cost_model.h"
#include "common/frame_params.h"
#include "common/params.h"
#include "common/renderer.h"
#include "scenes/catalog.h"

namespace mrr {

struct FrameOptions {
  std::string scene = "builtin:demo";
  std::string effect = "ssao";
  std::string mode = "mrr";
  std::string neverSlower;          // on|off; empty: neverSlowerDefault
  bool neverSlowerDefault = true;   // compare turns it off: it validates every stage of the method
  std::string costModelFile;
  std::string path = "cpu";
  int glDevice = -1;
  std::string gpuTiming = "auto";
  std::string size = "1280x720";
  std::optional<int> samples;
  int threads = 0;
  int seed = 0;  // --seed (Settings::seed)
  std::string coarseGBuffer = "subsample";  // --coarse-gbuffer (Settings::renderCoarseGBuffer)
  std::optional<int> camera;
  std::string eye, target, up, lightDir, frameFile;
  std::string blendMaterials = "opaque";
  std::optional<float> fov;
  bool flipUp = false, noFlipUp = false;
  std::optional<float> aoRadius;
  std::optional<float> aoBias;
  bool texelDepth = false;
  std::optional<int> shadowMapSize;
  std::optional<float> lightAngle;
  std::optional<float> giRadius;
  std::optional<float> tauN, tauZ;
  std::vector<int> disabledLevels;
  std::optional<double> memoryLimitGiB;
  bool quiet = false;
  std::vector<float> sigma2, weights;  // per level (empty: the effect's defaults, Table 1)
  std::optional<int> effectCap, effectFirstLevel;  // SPEC §12: mrr-effect's widening
  std::optional<float> effectScale;
  std::optional<float> effectPosterior;       // SPEC §12.2: τ_v (0: off)
  std::optional<int> effectPosteriorFinest;   // SPEC §12.2: ℓ_v
  std::optional<float> ppd;            // SPEC §13: viewing conditions
  std::string gaze;                    // "X,Y", a full-res pixel (empty: no foveation)
  std::string foveate = "on";          // on|off: off measures only
  std::string prevFrame;               // a frame file (empty: no motion term)

  // Registers every row of the frame-parameter table on `app` (a subcommand) as an option.
  void add(CLI::App& app);
  // The frame's Settings; throws MrrError naming the option for a bad value.
  Settings settings() const;
  // The never-slower rule's costs: --cost-model, else the built-in defaults of `forPath`.
  // Comparisons pass the oracle's for both paths, so both take the same decision.
  CostModel costModel(const std::string& forPath) const;
  SceneRequest sceneRequest() const;
  // The frame as a frame file (frontend/frame_file.h): the camera and light as resolved, so that
  // reading it back renders the same bits; the parameters as the settings hold them.
  nlohmann::json frame(const ResolvedScene& rs, const Settings& s) const;
  void checkPath(bool bothAllowed = false) const;
  PathOptions pathOptions() const { return {glDevice, gpuTiming}; }
};

}  // namespace mrr
