#pragma once
// The one tolerance table for the port against the oracle (SPEC §8): every rule has a
// per-pixel threshold, the share of pixels allowed over it, an RMS bound, and why. Tests
// and `mrr compare` (compare/parity/parity.cpp) read it. No tolerance is written anywhere else.
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

namespace mrr {

struct ToleranceRule {
  std::string_view stage;
  double pixelThreshold;  // |Δ| above it counts as a differing pixel (the stage's own unit)
  double shareOver;       // share of pixels allowed over the threshold
  double rmsBound;        // bound on the RMS of Δ (infinity: not used)
  std::string_view why;
};

inline constexpr double kNoRms = std::numeric_limits<double>::infinity();

// ".same_input" rules compare the port's stage with the oracle's stage run on the port's own
// inputs (cascade awareness); the others compare end to end with the oracle.
inline constexpr ToleranceRule kTolerances[] = {
    {"gbuffer.hit", 0.5, 0.01, kNoRms,
     "triangle-edge pixels: ray casting and rasterisation pick different triangles"},
    {"gbuffer.depth", 1e-3, 0.01, kNoRms,
     "relative |Δz|/z: perspective-correct interpolation vs barycentrics of the hit"},
    {"gbuffer.normal", 1e-4, 0.01, kNoRms,
     "1 − N·N': interpolation order of the vertex normals; at creases (the oracle's normal turns > 8° to a "
     "neighbour) the rasteriser's sub-pixel snapping may pick the other facet, allowed and counted apart"},
    {"gbuffer.albedo", 1e-6, 0.03, kNoRms,
     "the same factor and texel on both paths, but coplanar overlapping meshes (the arcade's decals) z-fight: the "
     "nearest ray hit and the depth test pick different ones (arcade 320x180: 2.4% at L1), besides triangle-edge "
     "pixels and a texture coordinate within rounding of a texel border (barycentric vs perspective-correct)"},
    {"edges", 0.5, 0.02, kNoRms, "inherited from the G-buffer's triangle-edge pixels"},
    {"edges.same_input", 0.5, 0.0, kNoRms,
     "exact outside the guard band (measures within 1e-4 of τ_n or τ_z, relative), where rounding may flip a pixel"},
    {"masks.same_input", 0.5, 0.0, kNoRms,
     "max-pools and stencils of the same edges are exact; S_ℓ outside its guard band (0 < a_ℓ ≤ 1e-4)"},
    {"marks.same_input", 0.5, 0.0, kNoRms,
     "SPEC §12.2: min, max and one subtraction of the same floats, compared with the same τ_v: exact"},
    {"alpha.same_input", 1e-6, 0.0, kNoRms, "the blur sums the same weights in the same order in float"},
    {"stencil", 0.5, 0.05, kNoRms, "one edge pixel moved upstream dilates by r_ℓ in S_ℓ"},
    {"eccentricity", 1e-5, 0.0, kNoRms,
     "SPEC §13: d² is a whole number on both paths; its square root and the division by ppd round alike but for the last bit"},
    {"motion", 1e-2, 0.02, kNoRms,
     "inherited: the reprojected point is the G-buffer's position, which differs at triangle-edge pixels"},
    {"motion.same_input", 1e-3, 0.001, kNoRms,
     "the same float32 steps; GLSL dot and multiply-add contraction round the last bits differently (|v| up to tens of pixels)"},
    {"levellimit", 0.5, 0.02, kNoRms, "inherited: motion at triangle-edge pixels may cross a threshold"},
    {"levellimit.same_input", 0.5, 0.001, kNoRms,
     "the eye's levels are integer tests (exact); motion's may flip where |v| lies on a threshold within rounding"},
    {"rule.pcf_counts", 0.5, 0.02, kNoRms,
     "H_a and H_p, relative: a PCF sample on the knife's edge of a blocker test flips its 8x8 block's pixels "
     "(shadows 203x149: at most 2 of 494 samples differ)"},
    {"rule.reach", 0.5, 0.05, kNoRms,
     "R_0, relative: an edge sample block that flips (the edges' triangle-edge pixels, each block the OR of 8) moves "
     "the reach by up to (2 ceil(r_0 / 8) + 1)^2 blocks"},
    {"fallback", 0.5, 0.0, kNoRms,
     "the never-slower decision (SPEC §11): the same cost model on both paths' stencil counts; a different decision "
     "gives the frames different levels, so it must agree (a gain within a few inherited pixels' cost of 0 is the "
     "one way it may not)"},
    {"ssao.same_input", 1e-4, 0.02, 2e-3,
     "GLSL sin/cos differ from libm in the last bits: a sample at a texel border may change texel"},
    {"ssao", 0.05, 0.02, 2e-2,
     "inherited: receivers at G-buffer triangle-edge pixels, and samples landing on them, change"},
    {"bilateral.same_input", 1e-5, 0.0, 1e-6, "the same taps and weights summed in the same order in float"},
    {"blend.same_input", 1e-5, 0.0, 1e-6,
     "the same four taps, weights and erratum-corrected blend in float; only last-bit rounding may differ"},
    {"final", 1e-3, 0.01, 2e-3, "end to end: the G-buffer's triangle-edge pixels, passed down the cascade"},
    {"temporal", 1e-3, 0.02, 5e-3,
     "end to end: the final image's and the G-buffer's differences, and a history tap whose depth or normal test "
     "flips with them"},
    {"temporal.same_input", 1e-5, 0.001, 1e-4,
     "SPEC 14: the same float32 steps on the same images; GLSL's division and the driver's multiply-add contraction "
     "round the last bits of q and z' differently, so a tap on a pixel border or a depth at the tolerance may flip"},
    {"shaded", 0.02, 0.05, 2e-2,
     "inherited: the final image's differences (SSGI's up to its 0.02) times albedo and light, and the G-buffer's "
     "triangle-edge and z-fighting pixels, where sky meets geometry or another albedo shows (arcade 320x180: 6.8%)"},
    {"shaded.same_input", 1e-5, 0.001, 1e-5,
     "GLSL dot and the driver's multiply-add contraction round the last bits differently from the oracle's "
     "-ffp-contract=off"},
    {"shadowmap.depth", 1e-2, 0.005, kNoRms,
     "|Δ| in texels (the bias is in texels too): raster vs ray depth rounding is ~1e-3 texel at 2048²; a texel centre "
     "a triangle edge passes through may hit another surface (arcade 1024²: 0.24%)"},
    {"shadowtest", 0.5, 0.002, kNoRms, "inherited: G-buffer triangle-edge pixels and the map's edge texels"},
    {"shadowtest.same_input", 0.5, 0.0005, kNoRms,
     "only a receiver within rounding of its texel's stored depth, or of a texel border, may flip"},
    {"ssm", 0.05, 0.005, 3e-2,
     "inherited: receivers at G-buffer edge pixels, or taps on the map's edge texels, flip (arcade 0.24%)"},
    {"ssm.same_input", 1e-6, 0.002, 1e-2,
     "GLSL division may round the filter width differently: a PCF tap on a texel border moves by one texel, and a "
     "pixel whose taps straddle the shadow's edge changes by k/N (arcade 320x180: one pixel, by 4/16)"},
    {"ssgi.direct.same_input", 1e-5, 0.0005, 1e-4,
     "GLSL dot and normalise round differently in the last bits; the one-tap test may flip at a border"},
    {"ssgi", 0.02, 0.02, 2e-2,
     "inherited: every receiver whose samples land on a G-buffer edge texel gets another sender (arcade: 1.2%)"},
    {"ssgi.same_input", 1e-4, 0.005, 1e-4,
     "GLSL sin/cos differ from libm in the last bits: a sample at a texel border may change sender"},
};

// The guard band around a threshold (edges: τ_n, τ_z, relative; stencils: a_ℓ > 0, absolute):
// the two paths' pre-threshold values agree to float rounding, so only pixels this close to a
// cutoff may fall on different sides of it (compare/parity/parity.cpp reports the band's size).
inline constexpr float kGuardBand = 1e-4f;

// The G-buffer normal's crease band: 1 − N·N' between neighbouring pixels of the oracle above
// which a triangle edge runs between them, where the rasteriser's sub-pixel snapping may pick
// the other facet (compare/parity/parity.cpp; the gbuffer.normal rule's why).
inline constexpr float kCreaseTurn = 0.01f;  // about 8°

// `mrr probe --path both` marks a value as parted when |Δ| > this × max(1, |a|, |b|): above
// float rounding of one stage, below any difference a bug makes.
inline constexpr double kProbeRelativeDifference = 1e-5;

// The noise-aware verdict (`compare --noise-aware`, docs/spec.md §8; compare/metrics/noise_stats.h):
// for the stochastic stages (SSAO's and SSGI's raw.Lℓ, and sub.Lℓ, final, shaded downstream)
// the oracle renders kNoiseSeeds frames with independent sampling seeds; each pixel of the
// subject is tested against their mean and spread, and the frame's and each region's bias
// against the spread of the seeds' own biases.
struct NoiseRule {
  int seeds;               // K, the oracle's independent seeds
  unsigned firstSeed;      // their --seed values: firstSeed, firstSeed + 1, ...
  double pixelAlpha;       // family-wise false-alarm rate of the per-pixel test (Šidák over pixels × channels)
  double biasAlpha;        // family-wise false-alarm rate of the bias tests (Šidák over the regions)
  double sampleFloor;      // a pixel's spread is at least this many samples' worth: floor σ = this × scale / N
  double biasFloor;        // |relative bias| at or below it is never flagged (0.5%: below what a user sees)
  int minRegionPixels;     // regions with fewer pixels are not tested for bias on their own
  std::string_view why;
};

inline constexpr NoiseRule kNoiseRule = {
    16, 1000000u, 0.01, 0.01, 1.0, 0.005, 16,
    "a renderer with its own noise (another seed, blue noise) draws another sample of the same estimator: its pixels "
    "are judged by how far they stray from the oracle's mean in units of the oracle's own spread (Welch's t with "
    "Šidák's family-wise correction, as Mitsuba 3's tests do), and its average by whether its bias lies outside what "
    "the oracle's own seeds show; a pixel whose K seeds barely vary (one occluded sample among N) keeps one sample's "
    "worth of spread, so a rare sample is no bug"};

inline const ToleranceRule& tolerance(std::string_view stage) {
  for (const ToleranceRule& r : kTolerances)
    if (r.stage == stage) return r;
  throw std::out_of_range("no tolerance rule for stage " + std::string(stage));
}

}  // namespace mrr
