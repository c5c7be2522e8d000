#include "common/methods.h"

#include <algorithm>
#include <array>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "common/error.h"

namespace mrr {

namespace {

// The never-slower rule's switch, for every method it applies to.
constexpr MethodVariant kRuleVariants[] = {
    {"norule", Param::NeverSlower, "off", "without the never-slower rule (docs/spec.md §11)"},
};
// mrr-effect's parameters, and its switches (the ablation's arms, docs/spec.md §12).
constexpr Param kEffectParams[] = {Param::EffectCap,       Param::EffectFirstLevel,      Param::EffectScale,
                                   Param::EffectPosterior, Param::EffectPosteriorFinest, Param::EffectOnly,
                                   Param::EffectBudget,    Param::EffectTemporal,        Param::EffectHysteresis,
                                   Param::EffectTrim};
constexpr MethodVariant kEffectVariants[] = {
    {"c", Param::EffectCap, "", "the widening's cap, level pixels"},
    {"f", Param::EffectFirstLevel, "", "the finest level widened"},
    {"x", Param::EffectScale, "", "the footprint's multiplier"},
    {"p", Param::EffectPosterior, "", "the a-posteriori threshold tau_v (docs/spec.md §12.2)"},
    {"l", Param::EffectPosteriorFinest, "", "the finest level the a-posteriori term refines"},
    {"e", Param::EffectOnly, "1", "the ablation's effect-only arm (docs/spec.md §12.3)"},
    {"b", Param::EffectBudget, "", "the a-posteriori term's budget, a share of full's predicted time (docs/spec.md §12.4)"},
    {"t", Param::EffectTemporal, "", "the temporal term's lambda (docs/spec.md §14)"},
    {"h", Param::EffectHysteresis, "", "the a-posteriori marks' hysteresis (docs/spec.md §14.2)"},
    {"trim", Param::EffectTrim, "on", "a level > 0 shaded only where the blend reads it (docs/spec.md §12.5)"},
    {"notrim", Param::EffectTrim, "off", "every level's whole stencil shaded, read or not (docs/spec.md §12.5)"},
    {"noblur", Param::Sigma2, "0,0,0,0", "no mask blur (sigma2 0 at every level): the widening alone"},
    {"norule", Param::NeverSlower, "off", "without the never-slower rule (docs/spec.md §11)"},
};

// tiles' own temporal term, to compare with mrr-effect's (docs/spec.md §14): off unless asked.
constexpr Param kTilesParams[] = {Param::TilesTemporal};
constexpr MethodVariant kTilesVariants[] = {
    {"t", Param::TilesTemporal, "", "docs/spec.md §14's temporal term with this lambda, as mrr-effect's"},
};

constexpr uint8_t kAllLevels = 0b1111;

// One row a method: mode, name, aliases, label, help, spec; levels, shades, user levels; finds
// edges, mask builder, composition; never-slower, a posteriori, reference; parameters, variants;
// chart order, colour, marker; bench default, cold, fovea.
const MethodInfo kMethods[] = {
    {Mode::Mrr, "mrr", "multires", "mrr (the method)",
     "the paper's method: edges, blurred masks per level, blend coarse to fine", "§§2-5",
     kAllLevels, kAllLevels, true,
     true, MaskBuilder::Edges, Compose::Blend,
     true, false, false,
     {}, kRuleVariants,
     4, "#d62728", "o",
     true, true, true},
    {Mode::Full, "full", "", "full (the reference)",
     "every full-res pixel: the reference every error is measured against", "§9",
     0b0001, 0b0001, false,
     false, MaskBuilder::Full, Compose::Blend,
     false, false, true,
     {}, {},
     0, "#7f7f7f", "o",
     true, false, false},
    {Mode::Uniform1, "uniform-1", "", "uniform-1",
     "every pixel of the half level, then joint bilateral upsampling (what games ship)", "§9",
     0b0011, 0b0010, false,
     false, MaskBuilder::Uniform, Compose::JointBilateral,
     false, false, false,
     {}, {},
     1, "#1f77b4", "s",
     true, false, false},
    {Mode::Uniform2, "uniform-2", "", "uniform-2",
     "every pixel of the quarter level, then joint bilateral upsampling", "§9",
     0b0101, 0b0100, false,
     false, MaskBuilder::Uniform, Compose::JointBilateral,
     false, false, false,
     {}, {},
     2, "#17becf", "D",
     true, false, false},
    {Mode::Tiles, "tiles", "", "tiles",
     "16x16 tiles shaded at 1x1, 2x2 or 4x4 by their edges, broadcast unfiltered (variable-rate shading)", "§9",
     0b0111, 0b0111, false,
     true, MaskBuilder::Tiles, Compose::Broadcast,
     false, false, false,
     kTilesParams, kTilesVariants,
     3, "#ff7f0e", "^",
     true, true, true},
    {Mode::MrrEffect, "mrr-effect", "", "mrr-effect (masks that see the effect)",
     "mrr with each level's mask widened by the effect's footprint before the blur, and an optional a-posteriori "
     "refinement",
     "§12",
     kAllLevels, kAllLevels, true,
     true, MaskBuilder::EffectEdges, Compose::Blend,
     true, true, false,
     kEffectParams, kEffectVariants,
     5, "#8c564b", "P",
     true, true, true},
};

constexpr bool methodRowsInEnumOrder() {
  for (size_t i = 0; i < std::size(kMethods); ++i)
    if (static_cast<size_t>(kMethods[i].mode) != i) return false;
  return true;
}

bool hasAlias(const MethodInfo& m, std::string_view name) {
  for (std::string_view rest = m.aliases; !rest.empty();) {
    const size_t comma = rest.find(',');
    if (name == rest.substr(0, comma)) return true;
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
  }
  return false;
}

std::vector<std::string> namesWhere(bool MethodInfo::*flag) {
  std::vector<const MethodInfo*> rows;
  for (const MethodInfo& m : kMethods)
    if (m.*flag) rows.push_back(&m);
  std::stable_sort(rows.begin(), rows.end(), [](auto* a, auto* b) { return a->chartOrder < b->chartOrder; });
  std::vector<std::string> names;
  for (const MethodInfo* m : rows) names.emplace_back(m->name);
  return names;
}

}  // namespace

bool MethodInfo::owns(Param p) const { return std::find(params.begin(), params.end(), p) != params.end(); }

std::span<const MethodInfo> methods() {
  static const bool ordered = methodRowsInEnumOrder();
  require(ordered, "internal: kMethods must list every Mode in enum order");
  return kMethods;
}

const MethodInfo& methodInfo(Mode mode) { return methods()[static_cast<size_t>(mode)]; }

const MethodInfo* findMethod(std::string_view name) {
  for (const MethodInfo& m : methods())
    if (m.name == name || hasAlias(m, name)) return &m;
  return nullptr;
}

std::string methodNames(std::string_view lastJoin) {
  std::string out;
  const auto rows = methods();
  for (size_t i = 0; i < rows.size(); ++i) {
    if (i) out += i + 1 == rows.size() ? std::string(lastJoin) : ", ";
    out += rows[i].name;
  }
  return out;
}

const MethodInfo& parseMethod(std::string_view name) {
  if (const MethodInfo* m = findMethod(name)) return *m;
  throw MrrError(optionName(Param::Method) + " " + std::string(name) + ": unknown method (expected " + methodNames() +
                 ")");
}

std::string toString(Mode mode) { return std::string(methodInfo(mode).name); }
Mode parseMode(const std::string& name) { return parseMethod(name).mode; }

bool ownedByAMethod(Param p) {
  return std::any_of(methods().begin(), methods().end(), [&](const MethodInfo& m) { return m.owns(p); });
}

std::string variantHelp(const MethodInfo& m) {
  std::string out;
  for (const MethodVariant& v : m.variants)
    out += (out.empty() ? "+" : ", +") + std::string(v.key) + (v.value.empty() ? "N" : "") + ": " + std::string(v.what);
  return out;
}

MethodSpec parseMethodSpec(std::string_view spec) {
  std::string text(spec);
  if (text.rfind("mrr-norule", 0) == 0) text = "mrr+norule" + text.substr(10);  // the old spelling
  const size_t plus = text.find('+');
  MethodSpec out;
  out.method = &parseMethod(std::string_view(text).substr(0, plus));
  const MethodInfo& m = *out.method;
  for (size_t at = plus; at != std::string::npos;) {
    const size_t next = text.find('+', at + 1);
    const std::string token = text.substr(at + 1, next == std::string::npos ? std::string::npos : next - at - 1);
    const MethodVariant* match = nullptr;
    std::string value;
    for (const MethodVariant& v : m.variants) {  // an exact fixed switch first ("noblur" before "n…")
      if (!v.value.empty() && token == v.key) { match = &v; value = v.value; break; }
    }
    for (const MethodVariant& v : m.variants) {
      if (match) break;
      if (v.value.empty() && token.size() > v.key.size() && token.compare(0, v.key.size(), v.key) == 0) {
        const std::string number = token.substr(v.key.size());
        char* end = nullptr;
        std::strtod(number.c_str(), &end);
        if (end && *end == '\0') { match = &v; value = number; }
      }
    }
    if (!match)
      throw MrrError("--methods " + std::string(spec) + ": " + std::string(m.name) + " has no variant +" + token +
                     (m.variants.empty() ? " (it takes none)" : " (it takes " + variantHelp(m) + ")"));
    out.values.emplace_back(match->param, value);
    at = next;
  }
  return out;
}

std::vector<std::string> methodSpecArgs(const MethodSpec& spec) {
  std::vector<std::string> args = {optionName(Param::Method), std::string(spec.method->name)};
  for (const auto& [param, value] : spec.values) {
    if (paramInfo(param).kind == ParamKind::Flag) {
      if (value == "1" || value == "true") args.push_back(optionName(param));
    } else {
      args.push_back(optionName(param) + "=" + value);
    }
  }
  return args;
}

std::string referenceMethod() {
  for (const MethodInfo& m : methods())
    if (m.reference) return std::string(m.name);
  throw MrrError("internal: the method table has no reference row");
}

namespace {
const char* builderName(MaskBuilder b) {
  switch (b) {
    case MaskBuilder::Full: return "full";
    case MaskBuilder::Uniform: return "uniform";
    case MaskBuilder::Tiles: return "tiles";
    case MaskBuilder::Edges: return "edges";
    case MaskBuilder::EffectEdges: return "effect_edges";
  }
  return "?";
}
const char* composeName(Compose c) {
  switch (c) {
    case Compose::Blend: return "blend";
    case Compose::JointBilateral: return "joint_bilateral";
    case Compose::Broadcast: return "broadcast";
  }
  return "?";
}
std::vector<int> levelList(uint8_t bits) {
  std::vector<int> out;
  for (int l = 0; l < 8; ++l)
    if (bits >> l & 1u) out.push_back(l);
  return out;
}
}  // namespace

nlohmann::json methodRowsJson() {
  nlohmann::json rows = nlohmann::json::array();
  for (const MethodInfo& m : methods()) {
    nlohmann::json owns = nlohmann::json::array(), variants = nlohmann::json::array();
    for (Param p : m.params) owns.push_back(paramInfo(p).key);
    for (const MethodVariant& v : m.variants)
      variants.push_back({{"key", v.key}, {"param", paramInfo(v.param).key}, {"value", v.value}, {"what", v.what}});
    rows.push_back({{"name", m.name}, {"aliases", m.aliases}, {"label", m.label}, {"help", m.help}, {"spec", m.spec},
                    {"levels", m.userLevels ? nlohmann::json("the user's") : nlohmann::json(levelList(m.levels))},
                    {"shades", m.userLevels ? nlohmann::json("the user's") : nlohmann::json(levelList(m.shades))},
                    {"finds_edges", m.findsEdges}, {"masks", builderName(m.masks)}, {"compose", composeName(m.compose)},
                    {"never_slower", m.neverSlower}, {"a_posteriori", m.aPosteriori}, {"reference", m.reference},
                    {"paper", m.mode == Mode::Mrr}, {"params", owns}, {"variants", variants},
                    {"chart_order", m.chartOrder}, {"colour", m.colour}, {"marker", m.marker},
                    {"bench_default", m.benchDefault}, {"cold", m.cold}, {"fovea", m.fovea}});
  }
  return rows;
}

std::string methodTableText() {
  std::string out;
  for (const MethodInfo& m : methods()) {
    out += std::string(m.name) + (m.aliases.empty() ? "" : " (also " + std::string(m.aliases) + ")") + ": " +
           std::string(m.help) + " (docs/spec.md " + std::string(m.spec) + ")\n";
    std::string levels;
    for (int l : levelList(m.shades)) levels += (levels.empty() ? "" : ", ") + std::to_string(l);
    out += "  shades: " + (m.userLevels ? std::string("the enabled levels (--disable-level)") : "level " + levels) +
           "; masks: " + builderName(m.masks) + (m.findsEdges ? " (from the edges)" : "") + "; composed by " +
           composeName(m.compose) + (m.neverSlower ? "; the never-slower rule applies" : "") +
           (m.aPosteriori ? "; a-posteriori term available" : "") + "\n";
    if (!m.params.empty()) {
      std::string owns;
      for (Param p : m.params) owns += (owns.empty() ? "" : " ") + optionName(p);
      out += "  its parameters: " + owns + "\n";
    }
    if (!m.variants.empty()) out += "  bench variants: " + variantHelp(m) + "\n";
  }
  return out;
}

std::vector<std::string> benchDefaultMethods() { return namesWhere(&MethodInfo::benchDefault); }
std::vector<std::string> coldMethods() {
  std::vector<std::string> names = namesWhere(&MethodInfo::cold);
  return names;
}
std::vector<std::string> foveaMethods() { return namesWhere(&MethodInfo::fovea); }

}  // namespace mrr
