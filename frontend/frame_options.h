#pragma once
// The options that say which frame to render, shared by render, probe, compare and explore:
// the fields the frame-parameter table's rows set (common/frame_params.h: names, kinds, help,
// defaults, which go in frame files and which the explore page may send) and one way from them
// to Settings, the scene request and the cost model.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/cost_model.h"
#include "common/frame_params.h"
#include "common/methods.h"
#include "common/params.h"
#include "common/renderer.h"
#include "scenes/catalog.h"

namespace mrr {

struct FrameOptions {
  // The rows that set one Settings field (common/frame_params.h: setParam): their text as given
  // on the command line, in a frame file or by explore, by parameter ("1" for a flag given).
  std::map<Param, std::string> given;
  void set(Param param, std::string text) { given[param] = std::move(text); }
  const std::string* value(Param param) const {
    const auto it = given.find(param);
    return it == given.end() ? nullptr : &it->second;
  }

  // The rows the front end resolves itself: the scene and camera, files, the path, compound values.
  std::string scene = "builtin:demo";
  std::string effect = "ssao";
  std::string mode = std::string(methodInfo(Mode::Mrr).name);
  bool neverSlowerDefault = true;   // compare turns it off: it validates every stage of the method
  std::string costModelFile;
  std::string path = "cpu";
  int glDevice = -1;
  std::string gpuTiming = "auto";
  std::string size = "1280x720";
  std::optional<int> samples;
  int threads = 0;
  std::string coarseGBuffer = "subsample";  // --coarse-gbuffer (Settings::renderCoarseGBuffer)
  std::optional<int> camera;
  std::string eye, target, up, lightDir, frameFile;
  std::string blendMaterials = "opaque";
  std::optional<float> fov;
  bool flipUp = false, noFlipUp = false;
  bool texelDepth = false;
  std::vector<int> disabledLevels;
  std::optional<double> memoryLimitGiB;
  bool quiet = false;
  std::string gaze;                    // "X,Y", a full-res pixel (empty: no foveation)
  std::string prevFrame;               // a frame file (empty: no motion term)
  std::optional<float> pan;            // --pan: the previous camera moved along its right axis (0: off)

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
  // The same without a resolved scene (a cache key): the camera and light left out, as the
  // scene request holds them as requested.
  nlohmann::json frame(const ResolvedScene* rs, const Settings& s) const;
  void checkPath(bool bothAllowed = false) const;
  PathOptions pathOptions() const { return {glDevice, gpuTiming}; }
};

}  // namespace mrr
