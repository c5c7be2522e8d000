#pragma once
// The stage list: every image of a frame, declared once (issue 16; Filament's DriverAPI.inc,
// Falcor's pass reflection). Each row names the image's part in the stages EXR and its rows in
// `mrr compare`, whether it is per level, its channels, the tolerance rules that judge it
// (common/tolerance.h), the pipeline step and shader that make it, and what it holds. The
// oracle's and the port's frames (common/frame.h), the stages EXR (compare/report.cpp), the
// comparison (compare/parity.cpp), its HTML page, the golden digests and the planted-fault
// catalogue (gpu/faults.cpp) all name parts through this list: adding a stage is one row here,
// one CPU function and one shader.
#include <algorithm>
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace mrr {

enum class Part {
  GBuffer,     // 1. G-buffer per level
  ShadowMap,   //    the light's shadow map (SSM, SSGI)
  ShadowTest,  //    the one-tap shadow test at full res (SSM, SSGI)
  Edges,       // 2. edge kinds and E
  TileRates,   // 3. tiles peer: each tile's rate
  Mask,        // 3. M_ℓ
  Alpha,       // 3. a_ℓ
  Stencil,     // 3. S_ℓ
  Raw,         // 4. the effect where S_ℓ = 1
  Sub,         // 4. c_ℓ after the bilateral blur
  Upsample,    // 5. ĉ_ℓ
  BlendAlpha,  // 5. α_ℓ
  Composite,   // 5. c'_ℓ
  LevelMap,    // 5. the finest level with α > 0
  Final,       // 5. the effect buffer
  Shaded,      // 6. the shaded image for viewing
};

struct PartInfo {
  Part part;
  std::string_view name;      // EXR part and compare row; per-level parts add ".L<ℓ>"
  bool perLevel;
  int step;                   // the pipeline step that makes it (SPEC's numbering, README)
  std::string_view stage;     // that step's stage: cpu_ref/<stage>.cpp, its timing name
  std::string_view shader;    // the port's shader file for it (gpu/shaders/)
  std::string_view channels;  // EXR channels; "effect:X" = X, or X.R/G/B for SSGI's RGB
  std::string_view endToEnd;  // tolerance rule against the oracle's stage ("" : none)
  std::string_view sameInput; // tolerance rule against the oracle on the port's inputs ("" : none)
  std::string_view what;      // one line, for pages and docs
};

inline constexpr PartInfo kParts[] = {
    {Part::GBuffer, "gbuffer", true, 1, "gbuffer", "gbuffer.frag",
     "depth P.x P.y P.z N.x N.y N.z albedo.R albedo.G albedo.B hit", "gbuffer.*", "",
     "the level's G-buffer: view depth, position, normal, albedo, hit"},
    {Part::ShadowMap, "shadowmap", false, 1, "shadowmap", "shadowmap.frag", "depth", "shadowmap.depth", "",
     "the light's shadow map: distance from the light plane (-1: no blocker)"},
    {Part::ShadowTest, "shadowtest", false, 1, "shadowtest", "shadowmap.frag", "lit", "shadowtest",
     "shadowtest.same_input", "the one-tap shadow test at full res (1 = lit)"},
    {Part::Edges, "edges", false, 2, "edges", "edges.frag", "normal depth background E shadow", "edges",
     "edges.same_input", "each edge kind (SSM adds shadow) and E, their OR"},
    {Part::TileRates, "tilerates", false, 3, "masks", "peers.frag", "rate", "stencil", "masks.same_input",
     "tiles: each 16x16 tile's rate, 0 (1x1), 1 (2x2) or 2 (4x4)"},
    {Part::Mask, "mask", true, 3, "masks", "masks.frag", "M", "", "masks.same_input",
     "the max-pooled edge mask M_l"},
    {Part::Alpha, "alpha", true, 3, "masks", "masks.frag", "a", "", "alpha.same_input",
     "the blurred mask a_l (1 at the coarsest level)"},
    {Part::Stencil, "stencil", true, 3, "masks", "masks.frag", "S", "stencil", "masks.same_input",
     "S_l = [a_l > 0] after the coverage closure"},
    {Part::Raw, "raw", true, 4, "effect", "ssao.frag ssm.frag ssgi.frag", "effect:c_raw", "<effect>",
     "<effect>.same_input", "the effect where S_l = 1 (0 elsewhere: never evaluated)"},
    {Part::Sub, "sub", true, 4, "bilateral", "bilateral.frag", "effect:c", "", "bilateral.same_input",
     "the sub-image c_l (SSAO: after the mask-aware bilateral blur)"},
    {Part::Upsample, "upsample", true, 5, "blend", "blend.frag", "effect:c_hat", "", "blend.same_input",
     "masked-bilinear c^_l at full res"},
    {Part::BlendAlpha, "blendalpha", true, 5, "blend", "blend.frag", "alpha", "", "blend.same_input",
     "alpha_l = min(a^_l w_l, 1)"},
    {Part::Composite, "composite", true, 5, "blend", "blend.frag", "effect:c_prime", "", "blend.same_input",
     "the composite c'_l after blending level l"},
    {Part::LevelMap, "levelmap", false, 5, "blend", "blend.frag", "level", "", "",
     "the finest level with alpha > 0 at each pixel"},
    {Part::Final, "final", false, 5, "blend", "blend.frag", "effect:Y", "final", "blend.same_input",
     "the effect buffer (= --out)"},
    {Part::Shaded, "shaded", false, 6, "shade", "shade.frag", "R G B", "shaded", "",
     "the shaded image for viewing (= --shaded)"},
};

inline constexpr const PartInfo& partInfo(Part part) { return kParts[static_cast<int>(part)]; }
static_assert([] {
  for (int i = 0; i < static_cast<int>(std::size(kParts)); ++i)
    if (static_cast<int>(kParts[i].part) != i) return false;
  return true;
}(), "kParts must list every Part in enum order");

// The part's name, with ".L<ℓ>" for a per-level part ("stencil.L2"); `level` is ignored for the others.
inline std::string partName(Part part, int level = -1) {
  const PartInfo& p = partInfo(part);
  std::string name(p.name);
  if (p.perLevel && level >= 0) name += ".L" + std::to_string(level);
  return name;
}

// The timing and progress name of the step that makes `part` ("gbuffer.L2", "effect.L1", "masks",
// "blend"): its `stage`, with ".L<ℓ>" for the per-level steps.
inline std::string stageName(Part part, int level = -1) {
  const PartInfo& p = partInfo(part);
  std::string name(p.stage);
  if (p.perLevel && level >= 0) name += ".L" + std::to_string(level);
  return name;
}

// The part's EXR channels, from its `channels` column: "effect:X" is X for a one-channel effect
// and X.R, X.G, X.B for SSGI's RGB (`effectChannels` 3).
inline std::vector<std::string> partChannels(Part part, int effectChannels = 1) {
  std::vector<std::string> names;
  std::string_view rest = partInfo(part).channels;
  while (!rest.empty()) {
    const size_t end = std::min(rest.find(' '), rest.size());
    const std::string_view token = rest.substr(0, end);
    rest = rest.substr(std::min(end + 1, rest.size()));
    if (token.substr(0, 7) != "effect:") {
      names.emplace_back(token);
    } else if (effectChannels == 1) {
      names.emplace_back(token.substr(7));
    } else {
      for (const char* c : {".R", ".G", ".B"}) names.push_back(std::string(token.substr(7)) + c);
    }
  }
  return names;
}

// The part a name starts with ("stencil.L2" → Stencil, "gbuffer.L0.depth" → GBuffer,
// "edges.normal" → Edges); false when none does.
inline bool partOf(std::string_view name, Part& out) {
  const std::string_view head = name.substr(0, name.find('.'));
  for (const PartInfo& p : kParts)
    if (p.name == head) {
      out = p.part;
      return true;
    }
  return false;
}

}  // namespace mrr
