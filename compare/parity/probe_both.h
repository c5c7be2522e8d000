#pragma once
// `mrr probe --path both`: one pixel through every stage on both paths, side by side, in
// pipeline order, marking the first value where the oracle and the port part.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace mrr {

struct ProbeRow {
  std::string key;     // "gbuffer.depth", "edges.normal.edge", "L1.c_raw", "L0.composite", …
  std::string oracle;  // the value as printed
  std::string port;
  bool differs = false;
  // The tolerance (common/tolerance.h) the value's stage is judged by end to end, its |Δ| in
  // that rule's unit, and whether |Δ| is within the rule's per-pixel threshold. rule "" : no
  // rule (exact values: taps, levels), within = !differs.
  std::string rule;
  double threshold = 0.0;
  double delta = 0.0;
  bool within = true;
  nlohmann::json oracleValue, portValue;  // the values themselves
};

// Both probes (cpu_ref/probe.h: probePixel) flattened in pipeline order: the G-buffer, the
// edges, then per level fine to coarse M, a, S, the raw value with the effect's own terms
// and the sub-image value, then the blend coarse to fine (taps, ĉ, α, c'), then the final.
// Numbers differ when |Δ| > kProbeRelativeDifference · max(1, |a|, |b|) (common/tolerance.h);
// everything else must be equal.
// Each row carries its tolerance: the stage's end-to-end rule (G-buffer depth and position
// relative to the depth, normals as 1 − N·N', the effect's rule for the raw and sub-image
// values, `final` for the blend's), else the same-input rule where the stage has no other.
std::vector<ProbeRow> probeSideBySide(const nlohmann::json& oracle, const nlohmann::json& port);

// The text `mrr probe --path both` prints; `renderer` names the port's GL renderer.
std::string formatProbeSideBySide(const nlohmann::json& oracle, const nlohmann::json& port,
                                  const std::string& renderer);

// The JSON form: {"oracle": …, "port": …, "rows": [...], "first_difference": key or null}.
nlohmann::json probeBothJson(const nlohmann::json& oracle, const nlohmann::json& port);

}  // namespace mrr
