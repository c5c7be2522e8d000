#pragma once
// The methods: one row each. A method is the sampling strategy of a frame (docs/spec.md §9): the
// paper's `mrr`, the reference `full`, the peers it is charted against, and `mrr-effect`
// (§12). Every method runs the same effect code on the same G-buffers; the row says which levels
// it keeps and shades, whether it finds edges, which mask builder makes its stencils (each
// backend implements every builder: common/driver.h), how its levels come together at full res,
// whether the never-slower rule (§11) and the a-posteriori term (§12.2) apply, the parameters it
// owns, and how the bench and the charts show it. The command line, frame files, the bench,
// compare, probe, explore (`/api/info`) and the reports read these rows; nothing else names a
// method. Adding one: docs/architecture.md, "Adding a method".
#include <bit>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "common/frame_params.h"

namespace mrr {

// The rows' keys, in table order (kMethods lists them in this order: static_assert in methods.cpp).
enum class Mode { Mrr, Full, Uniform1, Uniform2, Tiles, MrrEffect };

// Which mask builder makes a method's stencils (docs/spec.md §3, §9, §12). Each backend
// implements each one (FrameBackend::fullMasks … effectMasks, common/driver.h); the host-made
// ones read no image and are the same on every backend.
enum class MaskBuilder {
  Full,         // S_0 = every full-res pixel, nothing else (host-made)
  Uniform,      // S_k = every pixel of the one shaded level k (host-made)
  Tiles,        // 16×16 tiles' rates from E, then the rates' stencils (§9)
  Edges,        // the paper's pyramid from E: M_ℓ, a_ℓ, S_ℓ with the closure (§3)
  EffectEdges,  // M_ℓ widened by the effect's footprint at the edges first (§12)
};

// How a method's levels come together at full res (stage 5).
enum class Compose {
  Blend,           // masked-bilinear upsampling and α-blending coarse to fine (§5)
  JointBilateral,  // the one shaded level, joint-bilateral upsampled with level 0's G-buffer (§9)
  Broadcast,       // each tile's rate broadcast unfiltered (§9, as variable-rate shading)
};

// A bench variant's switch (`mrr-effect+c4+p0.15`): a short key and the parameter it sets, to
// the number after the key (`value` empty) or to a fixed value ("+norule": never_slower off).
struct MethodVariant {
  std::string_view key;    // "c", "norule"
  Param param;             // the frame parameter it sets (common/frame_params.h)
  std::string_view value;  // "" : the number after the key; else this value
  std::string_view what;   // one line, for the help and docs
};

struct MethodInfo {
  Mode mode;
  std::string_view name;     // --method, frame files, reports, the bench
  std::string_view aliases;  // other names accepted, comma separated ("multires"); "" for none
  std::string_view label;    // a few words for menus: "mrr (the method)"
  std::string_view help;     // one line for --help and docs
  std::string_view spec;     // the docs/spec.md section that defines it
  // Levels: bit ℓ of `levels` gives level ℓ a G-buffer, bit ℓ of `shades` runs the effect there;
  // with `userLevels` the user's --disable-level decides instead (the paper's Table 1 levels).
  uint8_t levels;
  uint8_t shades;
  bool userLevels;
  bool findsEdges;      // runs stage 2 (the edges) before its masks
  MaskBuilder masks;
  Compose compose;
  bool neverSlower;     // §11's rule may shade its frame at full res instead
  bool aPosteriori;     // §12.2's term may refine its masks after a coarser level is shaded
  bool reference;       // the method every error is measured against (full)
  std::span<const Param> params;  // the parameters only this method reads (frame files omit them otherwise)
  std::span<const MethodVariant> variants;  // the bench's switches for it
  // How the bench and the charts show it.
  int chartOrder;             // position in tables and legends
  std::string_view colour;    // matplotlib colour
  std::string_view marker;    // matplotlib marker
  bool benchDefault;          // in `mrr bench`'s default --methods
  bool cold;                  // rendered in fresh processes beside full by `bench --cold`
  bool fovea;                 // in the bench's foveation group by default

  bool findsEdgesOrBlends() const { return findsEdges || compose == Compose::Blend; }
  bool hostMadeMasks() const { return masks == MaskBuilder::Full || masks == MaskBuilder::Uniform; }
  // The edge-driven pyramid of §3 (mrr, mrr-effect): blurred masks, a closure, a guard band at a_ℓ = 0.
  bool blurredMasks() const { return masks == MaskBuilder::Edges || masks == MaskBuilder::EffectEdges; }
  bool peer() const { return compose != Compose::Blend; }
  // The finest level it shades (uniform-k: k, its only one).
  int finestShadedLevel() const { return std::countr_zero(static_cast<unsigned>(shades)); }
  bool owns(Param p) const;
};

// Every row, in table order.
std::span<const MethodInfo> methods();
const MethodInfo& methodInfo(Mode mode);
// The row a name or alias names; throws MrrError listing every name when none does.
const MethodInfo& parseMethod(std::string_view name);
const MethodInfo* findMethod(std::string_view name);  // nullptr when none
std::string toString(Mode mode);                      // the row's name
Mode parseMode(const std::string& name);              // parseMethod(name).mode
// "mrr, full, uniform-1, uniform-2, tiles or mrr-effect": every name, for help and errors.
std::string methodNames(std::string_view lastJoin = " or ");
// Whether some method owns `p` (frame files write it only for that method).
bool ownedByAMethod(Param p);

// A method as the bench names it: a row's name, then any of its variants' switches
// ("mrr-effect+c4+p0.15", "mrr+norule"); "mrr-norule" is the old spelling of "mrr+norule".
struct MethodSpec {
  const MethodInfo* method = nullptr;
  std::vector<std::pair<Param, std::string>> values;  // the parameters the switches set, in order
};
MethodSpec parseMethodSpec(std::string_view spec);  // throws MrrError naming the spec and what it accepts
// The spec as command-line words: "--method NAME" and one "--key=value" per switch.
std::vector<std::string> methodSpecArgs(const MethodSpec& spec);
// The name of the reference method (the row with `reference`: full).
std::string referenceMethod();
// The bench's default --methods, --cold methods and foveation methods, in chart order.
std::vector<std::string> benchDefaultMethods();
std::vector<std::string> coldMethods();
std::vector<std::string> foveaMethods();
// The variant switches a method takes, as help text ("+cN: …, +norule: …").
std::string variantHelp(const MethodInfo& m);
// Every row as JSON, as `mrr methods --json`, explore's /api/info and the bench's JSON give it
// (the reports' charts read their colours and order there).
nlohmann::json methodRowsJson();
// Every row as text, one block each, for `mrr methods` and docs.
std::string methodTableText();

}  // namespace mrr
