#pragma once
// Settings -> Constants (after XeGTAO's split of settings and constants). Settings are the user's knobs, with the
// paper's defaults (Table 1) and documented ranges; makeConstants() turns them into the
// numbers every stage reads. Both paths read Constants only, never Settings, so the port
// cannot see a different number than the oracle.
#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "common/methods.h"

namespace mrr {

enum class Effect { Ssao, Ssm, Ssgi };

std::string toString(Effect effect);
Effect parseEffect(const std::string& name);  // throws MrrError on an unknown name
// Whether the effect's estimator draws noise (SSAO's and SSGI's rotations and kernel, SPEC §7;
// SSM's PCF grid does not): its stages are stochastic, and a seed draws them anew.
constexpr bool isStochastic(Effect effect) { return effect == Effect::Ssao || effect == Effect::Ssgi; }

constexpr int kLevelCount = 4;           // full, ½, ¼, ⅛ (SPEC §0: L = 4)
constexpr int kMaxImageSize = 16384;     // per side; beyond it the G-buffers alone exceed RAM
constexpr int kMaxSsaoSamples = 1024;    // the paper stops at 256
constexpr int kMaxSsmSamples = 1024;     // PCF taps, a square n² (the paper: 10² .. 18²)
constexpr int kMaxSsgiSamples = 8192;    // the paper goes to 4224
constexpr int kMaxShadowMapSize = 8192;
constexpr int kTileSize = 16;            // tiles peer: full-res pixels per tile side (SPEC §9)

struct LevelSettings {
  bool enabled = true;
  float sigma2 = 0.0f;  // σ_ℓ² [0, 64]: variance of the mask blur, in level-ℓ pixels (Tab. 1)
  float weight = 1.0f;  // w_ℓ [0, ~]: blend weight, α_ℓ = min(â_ℓ · w_ℓ, 1) (Tab. 1)
};

struct EdgeSettings {
  float normalThreshold = 0.1f;  // τ_n [0, 2]: 1 − N(p)·N(q) above it is a normal edge (~26°)
  float depthThreshold = 0.02f;  // τ_z [0, ~]: |second difference of 1/z| / (1/z) above it
};

struct SsaoSettings {
  int samples = 64;          // N [1, kMaxSsaoSamples]
  float radius = 0.0f;       // R, world units; 0 = auto: kAutoRadiusFraction × the framed size
  // Depth bias as a fraction of R [0, 1] (docs/spec.md §6). 5% before the view-framed default (kBiasFractionBefore,
  // which the golden digests keep); 2% lets an object's small creases darken.
  float biasFraction = 0.02f;
  static constexpr float kBiasFractionBefore = 0.05f;
  // Occluder depth from the texel's tangent plane along the sample's ray (docs/spec.md §6.1),
  // not the texel-centre depth: keeps coarse levels from occluding themselves on slopes.
  bool tangentPlaneDepth = true;
  // The automatic R (docs/spec.md §6): a fraction of what the view frames (framedSize: the
  // view's height at the median depth of its surface). Before the view-framed default: 3% of the scene's
  // diagonal (kDiagonalFractionBefore), which the golden digests keep.
  static constexpr float kAutoRadiusFraction = 0.15f;
  static constexpr float kDiagonalFractionBefore = 0.03f;
};

struct SsmSettings {
  int samples = 196;             // PCF taps N = n² [1, kMaxSsmSamples], a perfect square
  int shadowMapSize = 2048;      // texels per side of the light's orthographic shadow map [16, 8192]
  float lightAngle = 0.05f;      // angular diameter of the light, radians (0, 0.5]: sets penumbra widths
  int blockerGrid = 6;           // blocker search taps per side [1, 16]
  float biasTexels = 1.5f;       // receiver offset along its normal and depth bias, in texels [0, 16]
};

struct SsgiSettings {
  int samples = 288;             // N [1, kMaxSsgiSamples] (the paper: 24, 80, 288, 1088, 4224)
  float radius = 0.0f;           // R, world units; 0 = auto: kAutoRadiusFraction × the framed size
  // Twice SSAO's, as before the view-framed default (then 6% of the scene's diagonal).
  static constexpr float kAutoRadiusFraction = 2.0f * SsaoSettings::kAutoRadiusFraction;
  static constexpr float kDiagonalFractionBefore = 0.06f;
};

// SPEC §14: a history tap shows the same surface as the pixel when its view depth is within δ of
// the depth the pixel's point has in the previous view (relative, as the bilateral blur's 5%) and its
// normal within acos κ ≈ 26° of the pixel's (as τ_n's edge test).
inline constexpr float kTemporalDepthTolerance = 0.05f;
inline constexpr float kTemporalNormalCos = 0.9f;

// mrr-effect only (SPEC §12): how far each level's edge mask is widened by the effect's footprint.
struct EffectMaskSettings {
  float scale = 1.0f;  // the footprint's multiplier [0, 16]; 0 = mrr's masks exactly
  int cap = 8;         // the widest widening, level pixels [0, 64]
  // The finest level widened [0, kLevelCount − 1]; finer ones keep mrr's M_ℓ. 1: level 0 is
  // mrr's (widening it cost more than it gained: docs/figures.md, "Masks that see the effect").
  int firstLevel = 1;
  // A posteriori (SPEC §12.2): τ_v, the local range of the next coarser level's result above
  // which a level pixel is refined, in the effect's units [0, 100]; 0 = off.
  float posterior = 0.0f;
  int posteriorFinest = 0;  // the finest level the a-posteriori term refines [0, kLevelCount − 1]
  // The ablation's "effect only" arm (SPEC §12.3, bench variant +e): each widened level keeps only
  // the pixels the widening adds (M'_ℓ ∧ ¬M_ℓ), each level below firstLevel nothing; both paths.
  bool effectOnly = false;
  // SPEC §12.4, the budget in predicted time: the a-posteriori term refines, most variation per
  // predicted nanosecond first, until the method's predicted rest reaches `budget` × full's
  // (SPEC §11's cost model); (0, 1], 0 = off (then τ_v alone decides, as before). With a budget,
  // τ_v is the least variation a candidate needs (0: any).
  float budget = 0.0f;
  // SPEC §14, the temporal term: λ, how much of the previous frame's result a pixel served by the
  // coarser levels keeps where reprojection finds the same surface, [0, 1); 0 = off. Used only
  // when the frame has a previous one (--prev-frame, --pan, the bench's camera paths).
  float temporal = 0.0f;
  // SPEC §14.2, the marks' hysteresis: a candidate the previous frame refined keeps its mark while
  // its variation stays above (1 − h) × what a new one needs, [0, 1); 0 = off.
  float hysteresis = 0.0f;
  // SPEC §12.5: each level ℓ ≥ 1 keeps only the pixels the blend reads (the taps of a full-res
  // pixel that no finer level covers with α = 1 a priori, and SSAO's blur around them); both paths.
  bool trim = false;
  // The a-posteriori term runs (coarse to fine shading, §12.2): a threshold or a budget.
  bool refines() const { return posterior > 0.0f || budget > 0.0f; }
  static constexpr int kDefaultCap = 8;
};

// Foveation and motion (SPEC §13): a per-pixel level limit from the gaze's eccentricity
// (Guenter et al. 2012's linear minimum angle of resolution) and from each pixel's screen motion
// against the previous frame's camera; off unless --gaze or --prev-frame is given.
struct FoveationSettings {
  // Pixels per degree of visual angle (> 0): a 0.7 m wide 4K display seen from 0.7 m, 3840·π/180 =
  // 67.02 (FLIP's default, compare/metrics/flip.h kFlipDefaultPpd, which the reports' FLIP takes from here).
  float ppd = static_cast<float>(3840.0 * 3.14159265358979323846 / 180.0);
  bool gaze = false;            // --gaze given
  int gazeX = 0, gazeY = 0;     // the full-res pixel the eye looks at, inside W×H
  bool foveate = true;          // false: the gaze only measures (eccentricity, rings); the eye limits nothing
  bool motion = false;          // --prev-frame given
  // The previous frame's camera (as a frame file records it): eye, target, up, vertical fov (radians).
  glm::vec3 prevEye{0.0f}, prevTarget{0.0f, 0.0f, -1.0f}, prevUp{0.0f, 1.0f, 0.0f};
  float prevYfov = 0.9f;
  int motionCap = 2;            // the coarsest level motion alone may ask for [0, kLevelCount − 1]
  float motionScale = 1.0f;     // multiplies the measured motion [0, 16] (1 = as measured)
  // --pan X (≠ 0), motion without a file: the previous camera is this frame's, its eye moved by
  // −X along its own right axis (previousView); the prev* fields above are then unused.
  bool panned = false;
  float pan = 0.0f;
  bool active() const { return gaze || motion; }
};

// SPEC §13's constants. Guenter et al. 2012 ("Foveated 3D graphics", SIGGRAPH Asia, §3): the
// minimum angle of resolution grows linearly with eccentricity, ω(e) = m·e + ω0; ω0 = 1/48° (the
// foveal acuity they assume, 20/20 vision's 1.25 arc minutes), m = 1.32 arc minutes per degree
// = 0.022°/° (the conservative end of the slopes their user study found, 1.32–1.65'/°).
inline constexpr double kMar0Degrees = 1.0 / 48.0;
inline constexpr double kMarSlope = 1.32 / 60.0;
// mrr: two level pixels per minimum angle of resolution (and per motion blur width): a level's
// values reach the screen through bilinear upsampling, whose response falls to 0 at its Nyquist
// frequency, so a level is asked to sample the finest resolvable detail twice.
inline constexpr double kSamplesPerMar = 2.0;

struct BilateralSettings {
  int radius = 2;              // taps each side [0, 8]; 0 disables the blur
  float sigmaSpatial = 1.5f;   // spatial Gaussian σ, level pixels
  float sigmaDepth = 0.05f;    // depth similarity σ, relative to the centre depth
  float normalPower = 16.0f;   // normal similarity max(N_p·N_q, 0)^p
};

struct Settings {
  int width = 1280;
  int height = 720;
  Effect effect = Effect::Ssao;
  Mode mode = Mode::Mrr;
  std::array<LevelSettings, kLevelCount> levels{};
  EdgeSettings edges;
  SsaoSettings ssao;
  SsmSettings ssm;
  SsgiSettings ssgi;
  BilateralSettings bilateral;
  EffectMaskSettings effectMask;  // mode mrr-effect only
  float tilesTemporal = 0.0f;     // mode tiles: SPEC §14's λ, for comparison (0: off)
  FoveationSettings foveation;    // modes mrr, mrr-effect and tiles (SPEC §13)
  // SPEC §11: in mode mrr, shade the frame at full res when the cost model predicts no gain.
  bool neverSlower = true;
  // SPEC §7: the sampling seed of SSAO's and SSGI's kernels and per-pixel rotations; 0 is mrr's
  // own sampling (the golden bits), any other value an independent draw of the same estimator.
  uint32_t seed = 0;
  // SPEC §1: the coarser levels' G-buffers rendered at their own pixel centres (the paper's
  // convention; --coarse-gbuffer render) instead of subsampled from level 0 (mrr's).
  bool renderCoarseGBuffer = false;

  // The sample count of the selected effect (what --samples sets).
  int samples() const;
  void setSamples(int n);
};

// The paper's defaults for an effect (Table 1; SPEC §3).
Settings defaultSettings(Effect effect);

// Checks every range above; throws MrrError naming the option and the limit.
void validateSettings(const Settings& settings);

struct LevelConstants {
  int index = 0;            // ℓ
  int scale = 1;            // s_ℓ = 2^ℓ
  int width = 0;            // padded W / s_ℓ
  int height = 0;           // padded H / s_ℓ
  bool enabled = true;      // has a G-buffer (and, unless !shaded, a sub-image)
  bool shaded = true;       // the effect runs here (false: level 0 of uniform-k, G-buffer only)
  float sigma2 = 0.0f;
  float weight = 1.0f;
  int blurRadius = 0;             // r_ℓ = ceil(3 σ_ℓ)
  std::vector<float> gaussian;    // 2 r_ℓ + 1 normalised weights (kernels.h)
};

struct Constants {
  int width = 0, height = 0;              // W×H
  int paddedWidth = 0, paddedHeight = 0;  // multiples of the coarsest scale (SPEC §0)
  Effect effect = Effect::Ssao;
  Mode mode = Mode::Mrr;
  std::array<LevelConstants, kLevelCount> levels{};
  int finestEnabled = 0;
  int coarsestEnabled = kLevelCount - 1;
  EdgeSettings edges;
  bool neverSlower = true;  // SPEC §11 (mode mrr only)
  bool renderCoarseGBuffer = false;  // SPEC §1: levels ≥ 1 rendered at their pixel centres, not subsampled
  struct Ssao {
    int samples = 0;
    float radius = 0.0f;
    float bias = 0.0f;
    bool tangentPlaneDepth = true;
    std::vector<glm::vec3> kernel;  // tangent-space hemisphere samples (kernels.h)
    uint32_t seed = 0;              // the sampling seed of the rotations (Settings::seed)
  } ssao;
  struct Ssm {
    int samples = 0;
    int grid = 0;                // n, with n² = samples
    int shadowMapSize = 0;
    float tanHalfAngle = 0.0f;   // penumbra width per unit of receiver-blocker distance, halved
    int blockerGrid = 0;
    float biasTexels = 0.0f;
  } ssm;
  struct Ssgi {
    int samples = 0;
    float radius = 0.0f;
    float patchArea = 0.0f;          // A_s = π R² / N (Ritschel et al. 2009)
    float minDistance2 = 0.0f;       // (R/4)²: the sender distance is clamped to it
    std::vector<glm::vec3> kernel;   // same generator as SSAO's
    uint32_t seed = 0;               // the sampling seed of the rotations (Settings::seed)
  } ssgi;
  EffectMaskSettings effectMask;  // mrr-effect (SPEC §12): its settings as given, nothing derived
  // SPEC §14: the temporal term, resolved for the frame's method (mrr-effect's λ, tiles' own;
  // 0 for every other method). It runs only when the frame has a previous one (RenderOptions::history).
  struct Temporal {
    float lambda = 0.0f;
    float depthTolerance = 0.0f;  // δ: a history tap is the same surface when |z_t − z'| ≤ δ z'
    float normalCos = 0.0f;       // κ: ... and its normal · this one's ≥ κ
    bool on() const { return lambda > 0.0f; }
  } temporal;
  // SPEC §13: the level limit. Off (active() false) leaves every mode exactly as before. The
  // settings as given, and the thresholds derived from them (makeFoveationConstants).
  struct Foveation : FoveationSettings {
    double mar0 = 0.0, marSlope = 0.0;  // ω0 (degrees) and m (degrees per degree), Guenter et al. 2012
    // Step 2: level ℓ ≥ 1 is allowed by the eye where d² ≥ radius2[ℓ] (d the distance to the gaze
    // in full-res pixels, an integer): exact integer thresholds made on the host.
    std::array<int64_t, kLevelCount> radius2{};
    // Step 4: level ℓ ≥ 1 is allowed by motion where (scale·v)² ≥ speed2[ℓ], v in full-res pixels.
    std::array<float, kLevelCount> speed2{};
  } foveation;
  struct Bilateral {
    int radius = 0;
    float sigmaDepth = 0.0f;
    float normalPower = 0.0f;
    std::vector<float> spatial;  // (2r+1)² spatial weights, row-major
  } bilateral;

  int samples() const;  // of the selected effect
  int channels() const { return effect == Effect::Ssgi ? 3 : 1; }
  bool needsShadowMap() const { return effect != Effect::Ssao; }

  // The enabled level coarser than ℓ that ℓ blends over, or -1 for the coarsest.
  int nextCoarserEnabled(int level) const;
  // This frame shaded at full res only (SPEC §11's fallback): level 0 alone, every pixel.
  void fallBackToFull();
};

// SPEC §12.5: how far past the blend's taps mrr-effect's trim keeps a level's pixels: SSAO's
// bilateral blur radius (its taps around a pixel the blend reads must be shaded, SPEC §4); SSM
// and SSGI are not blurred.
inline int trimMargin(const Constants& c) { return c.effect == Effect::Ssao ? c.bilateral.radius : 0; }

// Builds the constants for a W×H frame. `framedSize` (what the view frames, world units:
// scenes/default_light.h framedSize, ResolvedScene::framed) resolves the automatic SSAO and
// SSGI radii.
// Each level is enabled and shaded as the method's row says (common/methods.h): full level 0
// alone; uniform-k levels 0 (G-buffer only, for the joint bilateral upsampling) and k; tiles
// levels 0–2; mrr and mrr-effect the user's.
Constants makeConstants(const Settings& settings, float framedSize);
// SPEC §13: the foveation's constants (the level thresholds), as makeConstants fills them.
void makeFoveationConstants(const FoveationSettings& settings, Constants::Foveation& out);

}  // namespace mrr
