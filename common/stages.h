#pragma once
// The stage list: every image of a frame, declared once (Filament's DriverAPI.inc, Falcor's pass
// reflection). Each row names the image's part in the stages EXR and its rows in `mrr compare`,
// whether it is per level, its channels, the tolerance rules that judge it (common/tolerance.h),
// the pipeline step and shader that make it, and what it holds; and it carries the part's data:
// where its image lies in a FrameResult (an accessor that reads it in its EXR channel layout and
// writes it back), the parts its same-input check reads, and how a viewer shows it. The stages
// EXR (compare/report/report.cpp), `compare --against` (compare/parity/against.cpp), the compare
// page (compare/parity/html_report.cpp) and `mrr explore`'s layers (explore/layers.cpp) loop over
// the rows; the comparison (compare/parity/parity.cpp), the golden digests and the planted-fault
// catalogue (gpu/faults.cpp) name parts through it. docs/architecture.md ("Adding a stage") lists
// what a new stage takes.
//
// Below it, the timed stages: every name a frame's timings carry (FrameResult::timings, the
// reports' timings_ms, progress lines, the benchmark's and the rule sweep's stage medians), each
// with its cost class, the account it falls in for docs/spec.md §11's never-slower fits
// (compare/rule/rule.cpp). Both paths and renderFrame (common/driver.cpp) take every timing name
// from it; a name it does not know is an error where the fits read it: adding a timed sub-stage
// is one row there.
#include <algorithm>
#include <array>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.h"
#include "common/image.h"
#include "common/params.h"

namespace mrr {

// The timed stages, in pipeline order (kTimed below describes each).
enum class Timed {
  GBuffer,     // gbuffer.L<ℓ>
  ShadowMap,   // shadowmap
  ShadowTest,  // shadowtest
  Rule,        // rule (twice a frame: the early counts, then the stencils')
  Edges,       // edges
  Masking,     // masks (the method's M, a, S; the tiles' rates and masks)
  Stencils,    // stencils (the port: host-made stencils uploaded)
  Planes,      // planes.L<ℓ> (the oracle's SSAO occluder planes)
  Direct,      // direct.L<ℓ> (SSGI's direct light)
  Effect,      // effect.L<ℓ>
  Bilateral,   // bilateral.L<ℓ>
  Blend,       // blend
  Temporal,    // temporal (SPEC §14: with a previous frame)
  Shade,       // shade
  Total,       // total: the frame's wall clock
};

enum class Part {
  GBuffer,     // 1. G-buffer per level
  ShadowMap,   //    the light's shadow map (SSM, SSGI)
  ShadowTest,  //    the one-tap shadow test at full res (SSM, SSGI)
  Edges,       // 2. edge kinds and E
  Eccentricity,  // 3. SPEC §13: eccentricity from the gaze, degrees
  Motion,        // 3. SPEC §13: screen motion against the previous frame, pixels
  LevelLimit,    // 3. SPEC §13: the levels the eye and motion allow, and ℓ_min
  TileRates,   // 3. tiles peer: each tile's rate
  Marks,       // 3. SPEC §12.2: mrr-effect's a-posteriori marks (with τ_v, after the coarser level's shading)
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
  Temporal,    // 5. SPEC §14: the previous frame's result reprojected, and its weight
  Shaded,      // 6. the shaded image for viewing
};

struct FrameResult;  // common/frame.h

// A part's image in a frame (common/stage_images.cpp defines one per row). `read` gives it in its
// EXR channel layout, as `mrr render --stages` writes it: padded full-res grids cropped to W×H,
// byte images as floats, the shadow map's misses as -1; empty when the frame does not hold it (a
// disabled level, a stage the method or effect skips, a frame rendered without keepStages).
// `write` puts such an image in place of the frame's own (`compare --against`): a padded grid
// keeps its padding (allocated from the frame's constants when absent). `holds` is `read`'s
// emptiness without the copy. `level` is ignored by a part not per level. `view`, where the frame
// holds the part as a float image in its EXR layout already, is that image itself, to be read in
// place (the Python module's arrays, docs/python.md); null for the parts `read` converts.
struct PartImageAccess {
  bool (*holds)(const FrameResult& frame, int level);
  ImageF (*read)(const FrameResult& frame, int level);
  void (*write)(FrameResult& frame, int level, const ImageF& image);
  const ImageF* (*view)(const FrameResult& frame, int level);
};
extern const PartImageAccess kGBufferImage, kShadowMapImage, kShadowTestImage, kEdgesImage, kEccentricityImage,
    kMotionImage, kLevelLimitImage, kTileRatesImage, kMarksImage, kMaskImage, kAlphaImage, kStencilImage, kRawImage,
    kSubImage, kUpsampleImage, kBlendAlphaImage, kCompositeImage, kLevelMapImage, kFinalImage, kTemporalImage,
    kShadedImage;

// Where a part's image lies: the size of its EXR part.
enum class Grid {
  Level,   // level ℓ's padded grid (s_ℓ full-res pixels a texel, docs/spec.md §0)
  Screen,  // the W×H full-res pixels (a padded full-res grid cropped)
  Tiles,   // one texel per kTileSize² tile of the padded full-res grid (docs/spec.md §9)
  Light,   // the shadow map's texels: not the screen's grid
};

// Which level of an input part a same-input check reads, for the part at level ℓ.
enum class InputLevel {
  Same,         // ℓ (a part not per level: the part itself)
  Zero,         // level 0 (the full-res G-buffer)
  NextCoarser,  // the next coarser enabled level (docs/spec.md §12.2's marks); none at the coarsest
  Coarser,      // every coarser level (the blend's c'_coarser)
  Every,        // every level
};
// When a check reads the input: always, or only for some effects or methods (the part alone
// would not say: SSGI has a shadow test its edges do not read).
enum class InputWhen {
  Always,
  Ssm,        // the effect is SSM (its edges read the shadow test's kind, docs/spec.md §2)
  Footprint,  // the method widens its masks by the effect's footprint (mrr-effect, docs/spec.md §12)
  Peer,       // the method composes as a peer (docs/spec.md §9: G-buffers and tile rates)
};
struct PartInput {
  Part part;
  InputLevel level = InputLevel::Same;
  InputWhen when = InputWhen::Always;
};
// A row's inputs: a short constexpr list.
struct PartInputs {
  static constexpr int kMax = 8;
  std::array<PartInput, kMax> items{};
  int count = 0;
  constexpr PartInputs() = default;
  constexpr PartInputs(std::initializer_list<PartInput> list) {
    for (const PartInput& i : list) items[static_cast<size_t>(count++)] = i;  // > kMax: not a constant
  }
  constexpr const PartInput* begin() const { return items.data(); }
  constexpr const PartInput* end() const { return items.data() + count; }
  constexpr bool empty() const { return count == 0; }
};

// How a viewer (the compare page, explore) shows a part's values.
enum class Display {
  Binary,     // 0/1: black, white
  Levels,     // small integers (a level, a tile rate): one ramp colour each, 0 dark to 3 bright
  Effect,     // the effect's values: grey (SSGI: RGB), clamped to [0, 1]
  Scalar,     // non-colour data on the false-colour ramp over [lo, hi]
  Colour,     // linear RGB, shown sRGB-encoded
  GBuffer,    // bespoke: a view per channel group (depth, normal, albedo, position, hit)
  ShadowMap,  // bespoke: distance from the light plane, texels with no blocker apart
  Edges,      // bespoke: a binary view per edge kind, and E
};
struct PartView {
  Display display;
  std::string_view caption;   // what a viewer shows, a phrase (each viewer adds how: "…: 1 white, 0 black")
  float lo = 0.0f, hi = 0.0f;  // Scalar: the ramp's ends (hi <= lo: the image's own finite range)
  int channel = 0;            // Binary, Levels: the channel a view shows of a multi-channel part
  bool shadedOnly = false;    // values only where S_ℓ = 1 (never evaluated elsewhere): |Δ| there, the rest grey
};

struct PartInfo {
  Part part;
  std::string_view name;      // EXR part and compare row; per-level parts add ".L<ℓ>"
  bool perLevel;
  int step;                   // the pipeline step that makes it (SPEC's numbering, README)
  Timed stage;                // that step's timed stage (kTimed): cpu_ref/<its name>.cpp
  std::string_view shader;    // the port's shader file for it (gpu/shaders/)
  std::string_view channels;  // EXR channels; "effect:X" = X, or X.R/G/B for SSGI's RGB; trailing
                              // channels a frame lacks are left out (edges: shadow, SSM only)
  std::string_view endToEnd;  // tolerance rule against the oracle's stage ("" : none)
  std::string_view sameInput; // tolerance rule against the oracle on the port's inputs ("" : none)
  std::string_view what;      // one line, for pages and docs
  Grid grid;                  // where its image lies (its EXR part's size)
  const PartImageAccess* image;  // its image in a FrameResult (common/stage_images.cpp)
  PartInputs inputs;          // what its same-input check reads (cpu_ref/oracle.h's "Reads:"); none without one
  PartView view;              // how the compare page and explore show it
};

inline constexpr PartInfo kParts[] = {
    {Part::GBuffer, "gbuffer", true, 1, Timed::GBuffer, "gbuffer.frag",
     "depth P.x P.y P.z N.x N.y N.z albedo.R albedo.G albedo.B hit", "gbuffer.*", "",
     "the level's G-buffer: view depth, position, normal, albedo, hit", Grid::Level, &kGBufferImage, {},
     {Display::GBuffer, "the G-buffer: view depth, position, normal, albedo, hit"}},
    {Part::ShadowMap, "shadowmap", false, 1, Timed::ShadowMap, "shadowmap.frag", "depth", "shadowmap.depth", "",
     "the light's shadow map: distance from the light plane (-1: no blocker)", Grid::Light, &kShadowMapImage, {},
     {Display::ShadowMap, "distance from the light plane"}},
    {Part::ShadowTest, "shadowtest", false, 1, Timed::ShadowTest, "shadowmap.frag", "lit", "shadowtest",
     "shadowtest.same_input", "the one-tap shadow test at full res (1 = lit)", Grid::Screen, &kShadowTestImage,
     {{Part::GBuffer, InputLevel::Zero}, {Part::ShadowMap}},
     {Display::Binary, "the one-tap shadow test (1 = lit)"}},
    {Part::Edges, "edges", false, 2, Timed::Edges, "edges.frag", "normal depth background E shadow", "edges",
     "edges.same_input", "each edge kind (SSM adds shadow) and E, their OR", Grid::Screen, &kEdgesImage,
     {{Part::GBuffer, InputLevel::Zero}, {Part::ShadowTest, InputLevel::Same, InputWhen::Ssm}},
     {Display::Edges, "the edge image E, the OR of the kinds"}},
    {Part::Eccentricity, "eccentricity", false, 3, Timed::Masking, "limit.frag", "e", "eccentricity", "",
     "foveation: the angle from the gaze, degrees (d / ppd)", Grid::Screen, &kEccentricityImage, {},
     {Display::Scalar, "eccentricity from the gaze (degrees)", 0.0f, 30.0f}},
    {Part::Motion, "motion", false, 3, Timed::Masking, "limit.frag", "v", "motion", "motion.same_input",
     "motion: how far the pixel's surface point moved on screen since the previous frame, pixels", Grid::Screen,
     &kMotionImage, {{Part::GBuffer, InputLevel::Zero}},
     {Display::Scalar, "screen motion since the previous frame (pixels)", 0.0f, 16.0f}},
    {Part::LevelLimit, "levellimit", false, 3, Timed::Masking, "limit.frag", "fovea motion limit",
     "levellimit", "levellimit.same_input",
     "the coarsest level the eye allows, the coarsest motion allows, and the limit l_min (M_l = 0 below it)",
     Grid::Screen, &kLevelLimitImage, {{Part::GBuffer, InputLevel::Zero}},
     {Display::Levels, "the level limit ℓ_min: the finest level the eye and motion leave (finer levels' masks cleared)",
      0.0f, 0.0f, 2}},
    {Part::TileRates, "tilerates", false, 3, Timed::Masking, "peers.frag", "rate", "stencil", "masks.same_input",
     "tiles: each 16x16 tile's rate, 0 (1x1), 1 (2x2) or 2 (4x4)", Grid::Tiles, &kTileRatesImage,
     {{Part::Edges}, {Part::LevelLimit}},
     {Display::Levels, "each 16x16 tile's rate: 0 = 1x1, 1 = 2x2, 2 = 4x4"}},
    {Part::Marks, "marks", true, 3, Timed::Masking, "refinement_marks.frag refinement_budget.frag", "marks", "",
     "marks.same_input",
     "mrr-effect's a-posteriori term (SPEC 12.2): where the next coarser level's shaded result varies by more than "
     "tau_v over 3x3, or with a budget (SPEC 12.4, refinement_budget.frag) the most variation per unit of predicted "
     "cost that fits (after the level limit); M_l, a_l and S_l are then refined with them (refine_masks.frag)",
     Grid::Level, &kMarksImage,
     {{Part::Sub, InputLevel::NextCoarser}, {Part::Stencil, InputLevel::NextCoarser},
      {Part::GBuffer, InputLevel::NextCoarser}, {Part::LevelLimit}},
     {Display::Binary, "the a-posteriori marks this frame refined with (docs/spec.md §12.2, after the level limit)"}},
    {Part::Mask, "mask", true, 3, Timed::Masking, "masks.frag effect_masks.frag", "M", "", "masks.same_input",
     "the max-pooled edge mask M_l (mrr-effect: widened by the effect's footprint, M'_l; with tau_v: OR the marks)",
     Grid::Level, &kMaskImage,
     {{Part::Edges}, {Part::LevelLimit}, {Part::TileRates}, {Part::Marks},
      {Part::GBuffer, InputLevel::Zero, InputWhen::Footprint},
      {Part::ShadowMap, InputLevel::Same, InputWhen::Footprint}},
     {Display::Binary, "the mask M_ℓ the blur reads (mrr-effect: widened by the effect's footprint, with any marks)"}},
    {Part::Alpha, "alpha", true, 3, Timed::Masking, "masks.frag", "a", "", "alpha.same_input",
     "the blurred mask a_l (1 at the coarsest level)", Grid::Level, &kAlphaImage,
     {{Part::Edges}, {Part::LevelLimit}, {Part::TileRates}, {Part::Marks},
      {Part::GBuffer, InputLevel::Zero, InputWhen::Footprint},
      {Part::ShadowMap, InputLevel::Same, InputWhen::Footprint}},
     {Display::Scalar, "the blurred mask a_ℓ", 0.0f, 1.0f}},
    {Part::Stencil, "stencil", true, 3, Timed::Masking, "masks.frag", "S", "stencil", "masks.same_input",
     "S_l = [a_l > 0] after the coverage closure", Grid::Level, &kStencilImage,
     {{Part::Edges}, {Part::LevelLimit}, {Part::TileRates}, {Part::Marks},
      {Part::GBuffer, InputLevel::Zero, InputWhen::Footprint},
      {Part::ShadowMap, InputLevel::Same, InputWhen::Footprint}},
     {Display::Binary, "the stencil S_ℓ: shaded at this level"}},
    {Part::Raw, "raw", true, 4, Timed::Effect, "ssao.frag ssm.frag ssgi.frag", "effect:c_raw", "<effect>",
     "<effect>.same_input", "the effect where S_l = 1 (0 elsewhere: never evaluated)", Grid::Level, &kRawImage,
     {{Part::GBuffer}, {Part::Stencil}, {Part::ShadowMap}},
     {Display::Effect, "the effect before the blur, where S_ℓ = 1", 0.0f, 0.0f, 0, true}},
    {Part::Sub, "sub", true, 4, Timed::Bilateral, "bilateral.frag", "effect:c", "", "bilateral.same_input",
     "the sub-image c_l (SSAO: after the mask-aware bilateral blur)", Grid::Level, &kSubImage,
     {{Part::Raw}, {Part::Stencil}, {Part::GBuffer}},
     {Display::Effect, "the sub-image c_ℓ (SSAO: after the bilateral blur)", 0.0f, 0.0f, 0, true}},
    {Part::Upsample, "upsample", true, 5, Timed::Blend, "blend.frag", "effect:c_hat", "", "blend.same_input",
     "masked-bilinear c^_l at full res", Grid::Screen, &kUpsampleImage,
     {{Part::Sub}, {Part::Stencil}, {Part::Alpha}, {Part::GBuffer, InputLevel::Every, InputWhen::Peer},
      {Part::TileRates, InputLevel::Same, InputWhen::Peer}},
     {Display::Effect, "the masked-bilinear upsampled ĉ_ℓ"}},
    {Part::BlendAlpha, "blendalpha", true, 5, Timed::Blend, "blend.frag", "alpha", "", "blend.same_input",
     "alpha_l = min(a^_l w_l, 1)", Grid::Screen, &kBlendAlphaImage,
     {{Part::Stencil}, {Part::Alpha}, {Part::GBuffer, InputLevel::Every, InputWhen::Peer},
      {Part::TileRates, InputLevel::Same, InputWhen::Peer}},
     {Display::Scalar, "α_ℓ = min(â_ℓ w_ℓ, 1)", 0.0f, 1.0f}},
    {Part::Composite, "composite", true, 5, Timed::Blend, "blend.frag", "effect:c_prime", "", "blend.same_input",
     "the composite c'_l after blending level l", Grid::Screen, &kCompositeImage,
     {{Part::Upsample}, {Part::BlendAlpha}, {Part::Composite, InputLevel::Coarser},
      {Part::Sub, InputLevel::Every, InputWhen::Peer},
      {Part::GBuffer, InputLevel::Every, InputWhen::Peer}, {Part::TileRates, InputLevel::Same, InputWhen::Peer}},
     {Display::Effect, "the composite c′_ℓ after blending level ℓ"}},
    {Part::LevelMap, "levelmap", false, 5, Timed::Blend, "blend.frag", "level", "", "",
     "the finest level with alpha > 0 at each pixel", Grid::Screen, &kLevelMapImage, {},
     {Display::Levels, "the finest level with α > 0 at each pixel"}},
    {Part::Final, "final", false, 5, Timed::Blend, "blend.frag", "effect:Y", "final", "blend.same_input",
     "the blend's effect buffer (= --out; where SPEC 14's temporal term ran, --out is its result, part temporal)",
     Grid::Screen, &kFinalImage,
     {{Part::Composite, InputLevel::Every}, {Part::Sub, InputLevel::Every},
      {Part::GBuffer, InputLevel::Every, InputWhen::Peer},
      {Part::TileRates, InputLevel::Same, InputWhen::Peer}},
     {Display::Effect, "the final effect buffer"}},
    {Part::Temporal, "temporal", false, 5, Timed::Temporal, "temporal.frag", "weight effect:h effect:Y", "temporal",
     "temporal.same_input",
     "SPEC 14: the share lambda_p of the previous frame's result the pixel keeps (0: none), that result reprojected "
     "where it shows the same surface (h), and the term's result final' (the effect buffer, = --out)",
     Grid::Screen, &kTemporalImage,
     {{Part::Final}, {Part::GBuffer, InputLevel::Zero}, {Part::Stencil, InputLevel::Zero},
      {Part::Alpha, InputLevel::Zero}},
     {Display::Scalar, "λ_p, the share of the previous frame's result the pixel keeps (docs/spec.md §14)", 0.0f, 1.0f}},
    {Part::Shaded, "shaded", false, 6, Timed::Shade, "shade.frag", "R G B", "shaded", "",
     "the shaded image for viewing (= --shaded)", Grid::Screen, &kShadedImage,
     {{Part::GBuffer, InputLevel::Zero}, {Part::Final}, {Part::ShadowTest}},
     {Display::Colour, "the shaded image"}},
};

inline constexpr const PartInfo& partInfo(Part part) { return kParts[static_cast<int>(part)]; }
static_assert([] {
  for (int i = 0; i < static_cast<int>(std::size(kParts)); ++i)
    if (static_cast<int>(kParts[i].part) != i) return false;
  return true;
}(), "kParts must list every Part in enum order");
// Every row's accessor is checked by tests/common/stages_test.cpp: comparing an extern object's
// address with null is not a constant expression under the sanitizers' instrumentation.
static_assert([] {
  for (const PartInfo& p : kParts)
    if (p.view.caption.empty()) return false;
  return true;
}(), "every kParts row needs a caption");

// The part's name, with ".L<ℓ>" for a per-level part ("stencil.L2"); `level` is ignored for the others.
inline std::string partName(Part part, int level = -1) {
  const PartInfo& p = partInfo(part);
  std::string name(p.name);
  if (p.perLevel && level >= 0) name += ".L" + std::to_string(level);
  return name;
}

// The timing and progress name of the step that makes `part` ("gbuffer.L2", "effect.L1", "masks",
// "blend"): its `stage`, with ".L<ℓ>" for the per-level steps.
inline std::string stageName(Part part, int level = -1);  // defined with kTimed, below

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

// ---- The timed stages ----------------------------------------------------------------------

// Where a timed stage's time goes in SPEC §11's accounts: the sums and fits of compare/rule/rule.cpp
// (the rule sweep's frame and rests, the calibration's fits) read the classes, never the names.
enum class CostClass {
  Shared,      // paid alike by every mode before the rule decides (the full-res G-buffer, the shadow
               // map and its one-tap test): out of the frame the sweep compares modes by, and out of
               // both rests (SSM's 2048² map is 30 ms of a 40 ms small frame: its noise would decide)
  Detection,   // the method's own work before its decision: the edges (ε) and the masks (μ); in the
               // frame, out of the rest, in the early estimate's "from the edges on"
  Viewing,     // the shaded image for viewing: paid alike after the decision; in the frame, out of the rest
  Shading,     // the effect at its shaded pixels, and SSAO's blur: a, b, c, e per pixel, s, k₀ and k
  LevelPixel,  // per level pixel, shaded or not (d): SSAO's occluder planes, SSGI's direct light
  Rest,        // the rest of the frame after the decision, each priced by a figure of its own (the
               // coarse G-buffers g, the rule ρ, the blend β) or by the per-frame k₀ and k
  Total,       // the frame's wall clock, from the first stage to the last
};

// Which path times a stage (a stage of both is timed in the same order on both: parity tests).
enum class TimedOn { Both, Oracle, Port };

struct TimedInfo {
  Timed timed;
  std::string_view name;     // the timing name; per-level stages add ".L<ℓ>"
  bool perLevel;
  CostClass cost;            // its class (at a level above 0 for a per-level stage)
  CostClass costAtLevel0;    // its class at level 0 (the full-res G-buffer is paid before the decision)
  TimedOn on;
  std::string_view what;     // one line, for docs
};

inline constexpr TimedInfo kTimed[] = {
    {Timed::GBuffer, "gbuffer", true, CostClass::Rest, CostClass::Shared, TimedOn::Both,
     "level l's G-buffer: level 0 rasterised first, the coarser levels subsampled once the stencils are known (g)"},
    {Timed::ShadowMap, "shadowmap", false, CostClass::Shared, CostClass::Shared, TimedOn::Both,
     "the light's shadow map (SSM, SSGI)"},
    {Timed::ShadowTest, "shadowtest", false, CostClass::Shared, CostClass::Shared, TimedOn::Both,
     "the one-tap shadow test at full res (SSM, SSGI)"},
    {Timed::Rule, "rule", false, CostClass::Rest, CostClass::Rest, TimedOn::Both,
     "the never-slower rule's own counts (rho), twice a frame: H, H_a, H_p, B_l and the edge sample, then the stencils'"},
    {Timed::Edges, "edges", false, CostClass::Detection, CostClass::Detection, TimedOn::Both,
     "the edge kinds and E at full res (epsilon)"},
    {Timed::Masking, "masks", false, CostClass::Detection, CostClass::Detection, TimedOn::Both,
     "the method's M_l, a_l and S_l, or the tiles' rates and masks (mu)"},
    {Timed::Stencils, "stencils", false, CostClass::Rest, CostClass::Rest, TimedOn::Port,
     "the port: stencils made on the host (full, uniform-k, tiles, a fallback) uploaded for the stencil test"},
    {Timed::Planes, "planes", true, CostClass::LevelPixel, CostClass::LevelPixel, TimedOn::Oracle,
     "the oracle's SSAO occluder planes at every pixel of level l (d)"},
    {Timed::Direct, "direct", true, CostClass::LevelPixel, CostClass::LevelPixel, TimedOn::Both,
     "SSGI's direct light at every pixel of level l (d)"},
    {Timed::Effect, "effect", true, CostClass::Shading, CostClass::Shading, TimedOn::Both,
     "the effect at level l's stencilled pixels"},
    {Timed::Bilateral, "bilateral", true, CostClass::Shading, CostClass::Shading, TimedOn::Both,
     "SSAO's mask-aware bilateral blur of level l"},
    {Timed::Blend, "blend", false, CostClass::Rest, CostClass::Rest, TimedOn::Both,
     "upsample and blend, coarse to fine; the peers' composition (beta)"},
    {Timed::Temporal, "temporal", false, CostClass::Rest, CostClass::Rest, TimedOn::Both,
     "SPEC 14's temporal term: the previous frame's result reprojected and blended, and the history kept for the next"},
    {Timed::Shade, "shade", false, CostClass::Viewing, CostClass::Viewing, TimedOn::Both,
     "the shaded image for viewing"},
    {Timed::Total, "total", false, CostClass::Total, CostClass::Total, TimedOn::Both,
     "the whole frame, first stage to last (the wall clock, also where stages use timer queries)"},
};

inline constexpr const TimedInfo& timedInfo(Timed t) { return kTimed[static_cast<int>(t)]; }
static_assert([] {
  for (int i = 0; i < static_cast<int>(std::size(kTimed)); ++i)
    if (static_cast<int>(kTimed[i].timed) != i) return false;
  return true;
}(), "kTimed must list every Timed in enum order");

// The timing name of `t` ("gbuffer.L2", "rule"); `level` is ignored for a stage not per level.
inline std::string timedName(Timed t, int level = -1) {
  const TimedInfo& info = timedInfo(t);
  std::string name(info.name);
  if (info.perLevel && level >= 0) name.append(".L").append(std::to_string(level));
  return name;
}

inline std::string stageName(Part part, int level) { return timedName(partInfo(part).stage, level); }

// A timing name read back: its stage and level (-1 for a stage not per level).
struct TimedStage {
  Timed timed;
  int level = -1;
  const TimedInfo& info() const { return timedInfo(timed); }
  CostClass cost() const { return level == 0 ? info().costAtLevel0 : info().cost; }
};

// The stage a timing name names ("effect.L1" → Effect at level 1), or none: a per-level stage
// wants ".L<ℓ>" with ℓ < kLevelCount, the others their bare name.
inline std::optional<TimedStage> findTimed(std::string_view name) {
  const size_t dot = name.find('.');
  const std::string_view head = name.substr(0, dot);
  for (const TimedInfo& t : kTimed) {
    if (t.name != head) continue;
    if (!t.perLevel) return dot == std::string_view::npos ? std::optional<TimedStage>(TimedStage{t.timed}) : std::nullopt;
    const std::string_view rest = dot == std::string_view::npos ? std::string_view() : name.substr(dot);
    if (rest.size() != 3 || rest[1] != 'L' || rest[2] < '0' || rest[2] >= '0' + kLevelCount) return std::nullopt;
    return TimedStage{t.timed, rest[2] - '0'};
  }
  return std::nullopt;
}

// findTimed, where a name the list does not know is an error: a timed stage renamed on one side
// must not drop silently out of a sum (a term of the never-slower fits would read 0).
inline TimedStage parseTimed(std::string_view name) {
  const std::optional<TimedStage> t = findTimed(name);
  if (!t) {
    std::string known;
    for (const TimedInfo& i : kTimed) known += (known.empty() ? "" : ", ") + std::string(i.name) + (i.perLevel ? ".L<l>" : "");
    throw MrrError("timed stage '" + std::string(name) + "' is not in the stage list (common/stages.h kTimed: " + known + ")");
  }
  return *t;
}

}  // namespace mrr
