#pragma once
// Oracle against port, stage by stage (SPEC §8). Every stage the two paths share is
// compared twice where the stage allows it:
//   - end to end: the port's stage against the oracle's;
//   - on the same input ("cascade awareness"): the port's stage against the oracle's
//     function run on the port's own inputs (its G-buffer, edges, stencils, sub-images).
// A difference that starts upstream (a triangle-edge pixel of the G-buffer) then shows in the
// end-to-end figures of every later stage but not in their same-input figures, so a shader
// bug stands out from inherited noise. Every threshold comes from common/tolerance.h.
#include <algorithm>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "common/scene.h"
#include "common/tolerance.h"
#include "common/frame.h"
#include "compare/metrics/noise_stats.h"

namespace mrr {

// The figures of one comparison: over `pixels` compared, the largest |Δ|, the share of
// pixels with some channel's |Δ| over the rule's threshold, and the RMS of Δ.
struct DiffFigures {
  int64_t pixels = 0;
  double maxAbs = 0.0;
  double shareOver = 0.0;
  double rms = 0.0;
  int64_t over = 0;               // pixels over the threshold (outside the guard band)
  int64_t band = -1;              // guard-band size: pixels whose pre-threshold value lies within
                                  // ε of the cutoff (-1: no band for this check)
  int64_t overInBand = 0;         // pixels over the threshold inside the band (allowed)
  // The largest channel |Δ| at each compared pixel (0 elsewhere), on the stage's grid. Kept
  // only for checks that fail, so the report can show what the failing check measured.
  ImageF deltaMap;
  int worstX = -1, worstY = -1;  // where |Δ| is largest, in the stage's own grid
  // Within the rule: the RMS bound, and no more pixels over the threshold than its share —
  // where the rule allows any share, at least one pixel (a coarse level of a small frame has
  // so few pixels that one triangle-edge pixel is already over 1%).
  bool within(const ToleranceRule& rule) const {
    const double allowed = rule.shareOver > 0.0 ? std::max(1.0, rule.shareOver * static_cast<double>(pixels)) : 0.0;
    return static_cast<double>(over) <= allowed && rms <= rule.rmsBound;
  }
};

// |Δ| per pixel, the largest over the channels, where `include(i)` holds (every pixel when
// empty); a size mismatch counts every pixel as over. `band` (one flag per pixel, optional)
// is the guard band: differences there are allowed and counted apart (DiffFigures::overInBand).
DiffFigures diffImages(const ImageF& a, const ImageF& b, double threshold,
                       const std::function<bool(size_t)>& include = {}, const std::vector<char>* band = nullptr);
// 0/1 images (edges, masks, stencils, the shadow test): a pixel is over when they differ.
DiffFigures diffImages(const ImageU8& a, const ImageU8& b, const std::vector<char>* band = nullptr);
// Shadow-map depths in texels over the texels either map covers; a texel only one map
// covers is over by far.
DiffFigures diffShadowMaps(const ShadowMap& port, const ShadowMap& oracle, double thresholdTexels);

// "max|d| … rms … over …% of N": for logs and test messages.
std::ostream& operator<<(std::ostream& o, const DiffFigures& f);

// One check of a row: the rule, and the figures against it.
struct StageCheck {
  std::string rule;  // a stage of common/tolerance.h, or "noise" (the noise-aware test, kNoiseRule)
  DiffFigures figures;
  bool pass = true;
  // The noise-aware test's own figures (compare/parity/noise.h); then `figures` holds its summary: pixels
  // tested, |Δ| of the worst pixel from the seeds' mean, the share rejected, |bias| over the frame.
  std::optional<NoiseFigures> noise;
};

struct StageRow {
  std::string stage;  // e.g. "gbuffer.L0.depth", "edges", "stencil.L2", "sub.L1", "final"
  int level = -1;     // -1 for full-res stages
  int scale = 1;      // the stage's grid is W/scale × H/scale; 0: the shadow map's texels
  std::optional<StageCheck> endToEnd;   // against the oracle's stage
  std::optional<StageCheck> sameInput;  // against the oracle's function on the port's inputs
  bool pass() const { return (!endToEnd || endToEnd->pass) && (!sameInput || sameInput->pass); }
  // PASS; FAIL (the stage itself: its same-input check, or its only check, fails); or
  // UPSTREAM (end to end over its rule while the same-input check passes: inherited).
  std::string verdict() const;
  // The worst pixel of the check that decided the verdict, as a full-res pixel (the centre
  // of its level pixel) to pass to `mrr probe --pixel`; shadow-map texels for scale 0;
  // (-1, -1) when nothing differs.
  std::pair<int, int> worstPixel() const;
};

struct ParityResult {
  std::vector<StageRow> rows;  // in pipeline order
  Effect effect = Effect::Ssao;  // the frame's: which shader computes the effect rows
  Mode mode = Mode::Mrr;         // the frame's: mrr-effect's M'_l comes from effect_masks.frag
  // No stage FAILs. UPSTREAM rows do not fail the frame: their own computation matches the
  // oracle's on the same input, so the difference is inherited, and is blamed where it
  // starts (a G-buffer row over its own rule would FAIL there).
  bool pass() const;
  int inherited() const;  // rows with verdict UPSTREAM
  // The first row, in pipeline order, whose verdict is FAIL (empty when none): where a
  // shader bug starts.
  std::string firstFailing() const;
  // The row of a stage by its name ("raw.L0"), or null when the frame has none.
  const StageRow* row(const std::string& stage) const;
  // The port's shader file(s) that compute a row's stage, from the stage list ("ssao.frag" for
  // raw.L0 of an SSAO frame; "" for a row no shader makes, e.g. the never-slower decision).
  std::string shaderOf(const std::string& stage) const;
  // For an UPSTREAM row: the earlier rows that let differences through within their own rules
  // (pixels over their threshold, or inside their guard band), first to last, with where each
  // is worst: "raw.L0 (1 px over its threshold, worst at 111,74)". Empty when none did.
  std::string inheritedFrom(size_t row) const;
};

// Compares the port's frame with the oracle's (same scene, camera and constants; both
// rendered with keepStages so the per-level blend images exist).
ParityResult compareFrames(const FrameResult& oracle, const FrameResult& port, const DirectionalLight& light);

// The table `mrr compare` prints: one row per stage with the figures, the rule and the verdict.
// `owner`: whose inputs the same-input checks ran on, for the footnote ("the port's"; compare
// --against: "the file's").
std::string formatParityTable(const ParityResult& result, const std::string& owner = "the port's");

}  // namespace mrr
