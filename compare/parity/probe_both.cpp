#include "compare/parity/probe_both.h"

#include <cctype>
#include <cmath>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/stages.h"
#include "common/tolerance.h"

namespace mrr {

namespace {

using nlohmann::json;

std::string show(const json& v) {
  if (v.is_null()) return "-";
  if (v.is_number_float()) {
    char text[32];
    std::snprintf(text, sizeof text, "%.7g", v.get<double>());
    return text;
  }
  if (v.is_array()) {
    std::string out = "(";
    for (size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + show(v[i]);
    return out + ")";
  }
  return v.dump();
}

bool differs(const json& a, const json& b) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>(), y = b.get<double>();
    if (std::isnan(x) || std::isnan(y)) return std::isnan(x) != std::isnan(y);
    return std::fabs(x - y) > kProbeRelativeDifference * std::max({1.0, std::fabs(x), std::fabs(y)});
  }
  if (a.is_array() && b.is_array() && a.size() == b.size()) {
    for (size_t i = 0; i < a.size(); ++i)
      if (differs(a[i], b[i])) return true;
    return false;
  }
  return a != b;
}

// Appends every leaf under `path` of both documents; objects in the given key order first,
// then any other keys alphabetically (so nothing either side has is skipped).
void flatten(std::vector<ProbeRow>& rows, const std::string& label, const json& a, const json& b,
             const std::vector<std::string>& order = {}) {
  const bool objects = (a.is_object() || a.is_null()) && (b.is_object() || b.is_null()) && (a.is_object() || b.is_object());
  const bool arrays = a.is_array() && b.is_array() && !a.empty() && (a[0].is_object() || b[0].is_object());
  if (objects) {
    std::vector<std::string> keys = order;
    for (const json* doc : {&a, &b})
      if (doc->is_object())
        for (const auto& [k, v] : doc->items())
          if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
    for (const std::string& k : keys) {
      const json va = a.is_object() && a.contains(k) ? a[k] : json();
      const json vb = b.is_object() && b.contains(k) ? b[k] : json();
      if (va.is_null() && vb.is_null()) continue;
      flatten(rows, label.empty() ? k : label + "." + k, va, vb);
    }
    return;
  }
  if (arrays) {
    for (size_t i = 0; i < std::max(a.size(), b.size()); ++i)
      flatten(rows, label + "[" + std::to_string(i) + "]", i < a.size() ? a[i] : json(), i < b.size() ? b[i] : json());
    return;
  }
  ProbeRow row;
  row.key = label;
  row.oracle = show(a);
  row.port = show(b);
  row.differs = differs(a, b);
  row.oracleValue = a;
  row.portValue = b;
  rows.push_back(std::move(row));
}

// The largest |a_i − b_i| over the numbers of two values (arrays elementwise); -1 when they
// are not both numbers or same-sized arrays of numbers.
double largestDelta(const json& a, const json& b) {
  if (a.is_number() && b.is_number()) return std::fabs(a.get<double>() - b.get<double>());
  if (a.is_array() && b.is_array() && a.size() == b.size() && !a.empty()) {
    double worst = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
      const double d = largestDelta(a[i], b[i]);
      if (d < 0.0) return -1.0;
      worst = std::max(worst, d);
    }
    return worst;
  }
  return -1.0;
}

// The rule a row's value is judged by, from its key ("gbuffer.depth", "L1.c_raw", "L0.alpha").
std::string ruleFor(const std::string& key, const std::string& effect) {
  auto starts = [&](const std::string& prefix) { return key.rfind(prefix, 0) == 0; };
  if (starts("gbuffer.hit")) return "gbuffer.hit";
  if (starts("gbuffer.depth") || starts("gbuffer.position")) return "gbuffer.depth";
  if (starts("gbuffer.normal")) return "gbuffer.normal";
  if (starts("gbuffer.albedo")) return "gbuffer.albedo";
  auto ends = [&](const std::string& suffix) {
    return key.size() >= suffix.size() && key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (starts("edges.")) return ends(".edge") || key == "edges.E" ? "edges" : "";  // the measures: exact
  if (starts(partName(Part::Final))) return partName(Part::Final);
  if (!starts("L")) return "";
  const std::string field = key.substr(key.find('.') + 1);
  auto is = [&](const std::string& prefix) { return field.rfind(prefix, 0) == 0; };
  if (is("M") || is("S")) return "stencil";
  if (is("alpha") || is("a_hat") || is("c_hat") || is("composite")) return partName(Part::Final);
  if (is("a")) return "alpha.same_input";
  if (field == "c_raw" || field == "c") return effect;  // the effect's own terms (counts, angles): exact
  return "";  // taps: positions and weights, exact
}

// Fills the row's tolerance: |Δ| in the rule's unit against its threshold.
void judge(ProbeRow& row, const std::string& effect, double oracleDepth) {
  const json& a = row.oracleValue;
  const json& b = row.portValue;
  row.rule = ruleFor(row.key, effect);
  double d = largestDelta(a, b);
  if (row.rule.empty() || d < 0.0) {  // no rule, or not numbers: equal or not
    row.rule.clear();
    row.within = !row.differs;
    return;
  }
  if (row.rule == "gbuffer.depth") d /= std::max(std::fabs(oracleDepth), 1e-30);  // relative, as compare
  if (row.rule == "gbuffer.normal" && a.is_array() && b.is_array() && a.size() == 3 && b.size() == 3) {
    double dot = 0.0;
    for (size_t i = 0; i < 3; ++i) dot += a[i].get<double>() * b[i].get<double>();
    d = 1.0 - dot;
  }
  row.threshold = tolerance(row.rule).pixelThreshold;
  row.delta = d;
  row.within = d <= row.threshold;
}

// "L2": appended rather than "L" + …, which GCC 12 warns about falsely (-Wrestrict).
std::string levelLabel(size_t level) {
  std::string label = "L";
  label += std::to_string(level);
  return label;
}

}  // namespace

std::vector<ProbeRow> probeSideBySide(const json& o, const json& p) {
  std::vector<ProbeRow> rows;
  auto at = [](const json& doc, const std::string& key) { return doc.contains(key) ? doc[key] : json(); };
  // the probe's fields are named by the stage list's parts (common/stages.h)
  const std::string gbuffer = partName(Part::GBuffer), edges = partName(Part::Edges), final = partName(Part::Final);
  flatten(rows, gbuffer, at(o, gbuffer), at(p, gbuffer), {"hit", "depth", "position", "normal", "albedo"});
  flatten(rows, edges, at(o, edges), at(p, edges), {"normal", "depth", "background", "shadow", "E"});
  const std::string limit = partName(Part::LevelLimit);  // SPEC §13, with a gaze or a previous frame
  if (o.contains(limit) || p.contains(limit))
    flatten(rows, limit, at(o, limit), at(p, limit),
            {"gaze", "ppd", "foveate", "eccentricity_degrees", "fovea_level", "motion_pixels", "motion_cap", "motion_level",
             "limit"});
  const json lo = at(o, "levels"), lp = at(p, "levels");
  const size_t levels = std::max(lo.size(), lp.size());
  auto level = [&](const json& doc, size_t l) { return l < doc.size() ? doc[l] : json(); };
  auto pick = [](const json& lv, const std::vector<std::string>& keys) {
    json out = json::object();
    if (lv.is_object())
      for (const std::string& k : keys)
        if (lv.contains(k)) out[k] = lv[k];
    return out;
  };
  // Masks and the effect, fine to coarse (each level is independent there).
  const std::vector<std::string> maskKeys = {"M", "a", "S", "why", "c_raw", "ssao", "ssm", "ssgi", "c"};
  for (size_t l = 0; l < levels; ++l)
    flatten(rows, levelLabel(l), pick(level(lo, l), maskKeys), pick(level(lp, l), maskKeys), maskKeys);
  // The blend, coarse to fine, as it runs.
  const std::vector<std::string> blendKeys = {"taps", "c_hat", "a_hat", "alpha", partName(Part::Composite)};
  for (size_t l = levels; l-- > 0;)
    flatten(rows, levelLabel(l), pick(level(lo, l), blendKeys), pick(level(lp, l), blendKeys), blendKeys);
  flatten(rows, "finest_contributing_level", at(o, "finest_contributing_level"), at(p, "finest_contributing_level"));
  flatten(rows, final, at(o, final), at(p, final));
  // The tolerances, from the values kept in each row.
  const std::string effect = o.value("effect", std::string());
  const double depth = o.contains(gbuffer) && o[gbuffer].contains("depth") && o[gbuffer]["depth"].is_number()
                           ? o[gbuffer]["depth"].get<double>()
                           : 1.0;
  for (ProbeRow& r : rows) judge(r, effect, depth);
  return rows;
}

namespace {

// The pipeline step a probe row belongs to, as a heading with the port's shader that computes
// it (the stage list's), and the row's name within it: "L2.ssao.occluders" is "occluders" under
// "4. The effect at level 2 (ssao.frag)".
struct Section {
  std::string title;
  std::string name;
};

Section sectionOf(const std::string& key, const std::string& effect) {
  auto shader = [](Part part) { return std::string(partInfo(part).shader); };
  auto rest = [&](size_t from) { return from < key.size() ? key.substr(from) : key; };
  if (key.rfind("gbuffer.", 0) == 0) return {"1. The G-buffer at full resolution (" + shader(Part::GBuffer) + ")", rest(8)};
  if (key.rfind("shadow", 0) == 0) return {"1. The light's shadow map and test (" + shader(Part::ShadowMap) + ")", key};
  if (key.rfind("edges.", 0) == 0) return {"2. Edges (" + shader(Part::Edges) + ")", rest(6)};
  if (key.rfind("levellimit.", 0) == 0) return {"3. The level limit (" + shader(Part::LevelLimit) + ")", rest(11)};
  if (key.size() > 3 && key[0] == 'L' && std::isdigit(static_cast<unsigned char>(key[1])) && key[2] == '.') {
    const std::string level = key.substr(1, 1), what = key.substr(3);
    const std::string field = what.substr(0, what.find_first_of(".["));
    if (field == "M" || field == "a" || field == "S" || field == "why")
      return {"3. Masks and stencil, level " + level + " (" + shader(Part::Mask) + ")", what};
    if (field == "c_raw" || field == effect)
      return {"4. The effect, level " + level + " (" + effect + ".frag)", what};
    if (field == "c") return {"4. The sub-image, level " + level + " (" + shader(Part::Sub) + ")", what};
    return {"5. Upsample and blend, level " + level + " (" + shader(Part::Composite) + ")", what};
  }
  if (key == "final" || key == "finest_contributing_level") return {"5. The final image (" + shader(Part::Final) + ")", key};
  if (key.rfind("shaded", 0) == 0) return {"6. The shaded image (" + shader(Part::Shaded) + ")", key};
  return {"other", key};
}

}  // namespace

std::string formatProbeSideBySide(const json& o, const json& p, const std::string& renderer) {
  const std::vector<ProbeRow> rows = probeSideBySide(o, p);
  const std::string effect = o.value("effect", std::string("?"));
  std::string out = "pixel " + show(o.value("pixel", json())) + " of " + show(o.value("size", json())) + ", effect " +
                    effect + ", mode " + o.value("mode", std::string("?")) + ": the oracle (cpu_ref) beside the port (" +
                    renderer + "), step by step\n";
  // Columns as wide as what they hold (a value at most 44 characters).
  size_t name = 10, value = 8;
  for (const ProbeRow& r : rows) {
    name = std::max(name, sectionOf(r.key, effect).name.size());
    value = std::max({value, std::min<size_t>(r.oracle.size(), 44), std::min<size_t>(r.port.size(), 44)});
  }
  char line[640];
  auto add = [&](const std::string& a, const std::string& b, const std::string& c, const std::string& d, const std::string& e) {
    std::snprintf(line, sizeof line, "  %-*s  %-*s  %-*s  %-44s %s", static_cast<int>(name), a.c_str(),
                  static_cast<int>(value), b.c_str(), static_cast<int>(value), c.c_str(), d.c_str(), e.c_str());
    std::string text = line;
    text.erase(text.find_last_not_of(' ') + 1);
    out += text + "\n";
  };
  add("value", "oracle", "port", "how they are compared", "");
  std::string section;
  bool marked = false;
  int differing = 0;
  for (const ProbeRow& r : rows) {
    const Section s = sectionOf(r.key, effect);
    if (s.title != section) out += (section = s.title) + "\n";
    std::string verdict = r.within ? "" : "OVER";
    if (r.differs) {
      ++differing;
      verdict += (verdict.empty() ? "" : ", ") + std::string(marked ? "differs" : "<- the first difference");
      marked = true;
    }
    char how[128];
    if (r.rule.empty() && r.oracleValue.is_number())  // no tolerance of its own: a bookkeeping value
      std::snprintf(how, sizeof how, "must agree to %.0e x max(1, |value|)", kProbeRelativeDifference);
    else if (r.rule.empty())
      std::snprintf(how, sizeof how, "must be equal");
    else
      std::snprintf(how, sizeof how, "|d| %.3g vs %.3g allowed (%s)", std::fabs(r.delta), r.threshold, r.rule.c_str());
    add(s.name, r.oracle, r.port, how, verdict);
  }
  const long over = std::count_if(rows.begin(), rows.end(), [](const ProbeRow& r) { return !r.within; });
  out += differing == 0 ? "the paths agree at every stage for this pixel\n"
                        : std::to_string(differing) + " value(s) differ; the first marked is where the paths part; " +
                              std::to_string(over) + " over their tolerance\n";
  return out;
}

json probeBothJson(const json& o, const json& p) {
  json j;
  j["oracle"] = o;
  j["port"] = p;
  j["rows"] = json::array();
  j["first_difference"] = nullptr;
  for (const ProbeRow& r : probeSideBySide(o, p)) {
    j["rows"].push_back({{"key", r.key}, {"section", sectionOf(r.key, o.value("effect", std::string("?"))).title},
                         {"oracle", r.oracle}, {"port", r.port}, {"differs", r.differs},
                         {"rule", r.rule.empty() ? json() : json(r.rule)}, {"delta", r.delta},
                         {"threshold", r.threshold}, {"within", r.within}});
    if (r.differs && j["first_difference"].is_null()) j["first_difference"] = r.key;
  }
  return j;
}

}  // namespace mrr
