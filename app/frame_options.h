#pragma once
// The options that say which frame to render, shared by render, probe, compare and explore:
// one list of options (their names are also `mrr explore`'s frame parameters, docs/explore.md)
// and one way from them to Settings, the scene request and the cost model.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "common/cost_model.h"
#include "common/params.h"
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
  std::optional<int> camera;
  std::string eye, target, up, lightDir, frameFile;
  std::string blendMaterials = "opaque";
  std::optional<float> fov;
  bool flipUp = false, noFlipUp = false;
  float aoRadius = 0.0f;
  bool texelDepth = false;
  std::optional<int> shadowMapSize;
  std::optional<float> lightAngle;
  float giRadius = 0.0f;
  std::optional<float> tauN, tauZ;
  std::vector<int> disabledLevels;
  std::optional<double> memoryLimitGiB;
  bool quiet = false;
  std::string sigma2, weights;  // per level, "s0,s1,s2,s3" (empty: the effect's defaults, Table 1)

  // Registers every option on `app` (a subcommand).
  void add(CLI::App& app);
  // The frame's Settings; throws MrrError naming the option for a bad value.
  Settings settings() const;
  // The never-slower rule's costs: --cost-model, else the built-in defaults of `forPath`.
  // Comparisons pass the oracle's for both paths, so both take the same decision.
  CostModel costModel(const std::string& forPath) const;
  SceneRequest sceneRequest() const;
  // The frame as a frame file (app/frame_file.h): the camera and light as resolved, so that
  // reading it back renders the same bits; the parameters as the settings hold them.
  nlohmann::json frame(const ResolvedScene& rs, const Settings& s) const;
  void checkPath(bool bothAllowed = false) const;
};

}  // namespace mrr
