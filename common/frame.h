#pragma once
// The frame contract: the data every stage of both paths reads and writes, and the host logic
// both paths share. The oracle (cpu_ref/) fills these from its own images; the port (gpu/)
// from its textures, read back. Nothing here knows how a stage is computed: gpu/ includes
// nothing from cpu_ref/, and the port builds without Embree (CMake option MRR_BUILD_ORACLE).
//
// Data flows one way: scene → G-buffer → edges → masks → sub-images → blend → report.
// The stage list (common/stages.h) names every image here, its EXR part and its parity rule.
#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/camera.h"
#include "common/cost_model.h"
#include "common/image.h"
#include "common/params.h"
#include "common/scene.h"
#include "common/shader_constants.h"
#include "common/temporal.h"

namespace mrr {

// Stage 1 — one level's G-buffer (SPEC §1).
struct GBuffer {
  GBuffer() = default;
  GBuffer(int w, int h)  // all background
      : width(w), height(h), depth(w, h, 1), position(w, h, 3), normal(w, h, 3), albedo(w, h, 3), hit(w, h, 1) {}
  // Unfilled: for a renderer that writes every pixel, background included.
  static GBuffer uninitialised(int w, int h);

  int width = 0, height = 0;
  ImageF depth;     // linear view depth z > 0 (0 on background)
  ImageF position;  // view-space position, 3 channels
  ImageF normal;    // view-space shading normal, unit, facing the camera, 3 channels
  ImageF albedo;    // base colour, 3 channels
  ImageU8 hit;      // 1 = geometry, 0 = background

  glm::vec3 positionAt(int x, int y) const {
    return {position.at(x, y, 0), position.at(x, y, 1), position.at(x, y, 2)};
  }
  glm::vec3 normalAt(int x, int y) const { return {normal.at(x, y, 0), normal.at(x, y, 1), normal.at(x, y, 2)}; }
};

// The directional light's shadow map (SPEC §6 SSM): orthographic, fitted to the scene's
// bounds. Used by the shadow edges (SPEC §2), by SSM's PCSS and by SSGI's one-tap sender shadow.
struct ShadowMap {
  int size = 0;
  float texel = 0.0f;              // world units per texel
  float farDepth = 0.0f;           // distance from the light plane to the bounds' farthest corner
  glm::vec3 origin{0.0f};          // corner of texel (0, 0) on the light plane
  glm::vec3 right{1, 0, 0}, up{0, 0, 1}, forward{0, -1, 0};  // forward = the light's direction
  ImageF depth;                    // distance from the light plane to the first hit; kNoBlocker on a miss

  static constexpr float kNoBlocker = mrr::kNoBlocker;  // common/shader_constants.h

  // Continuous texel coordinates (u, v) and the distance from the light plane, of a world point.
  glm::vec3 lightCoordinates(const glm::vec3& world) const {
    const glm::vec3 d = world - origin;
    return {glm::dot(d, right) / texel, glm::dot(d, up) / texel, glm::dot(d, forward)};
  }
  // The stored depth at the texel holding (u, v); outside the map nothing blocks.
  float depthAt(float u, float v) const {
    if (!(u >= 0.0f && v >= 0.0f && u < static_cast<float>(size) && v < static_cast<float>(size))) return kNoBlocker;
    return depth.at(static_cast<int>(u), static_cast<int>(v));
  }
};

// The light's frame fitted to the bounds: basis, origin, texel size and depth range, with
// `depth` left empty. One function for both paths, so both render the same map texel for texel.
ShadowMap shadowMapFrame(const DirectionalLight& light, const Bounds& bounds, int size);

// Stage 2 — the edge image E (SPEC §2), each kind kept apart.
struct EdgeImages {
  ImageU8 normal;      // first derivative of N above τ_n
  ImageU8 depth;       // second derivative of 1/z above τ_z
  ImageU8 background;  // a hit pixel with a background 4-neighbour
  ImageU8 shadow;      // a hit pixel whose one-tap shadow test differs from a hit 4-neighbour's (SSM only)
  ImageU8 combined;    // E = OR of the kinds
};

// Stage 3 — one level of the mask pyramid (SPEC §3).
struct MaskLevel {
  ImageU8 mask;     // M_ℓ: 2×2 max-pool chain of E
  ImageF alpha;     // a_ℓ = G(σ_ℓ²) ∗ M_ℓ (≡ 1 at the coarsest enabled level); empty if disabled
  ImageU8 stencil;  // S_ℓ = [a_ℓ > 0], closed from fine to coarse; empty if disabled
  // SPEC §12.5 (mrr-effect's trim): D_ℓ, the level pixels the blend reads; S_ℓ ∧= D_ℓ, and the
  // a-posteriori refinement keeps it. Empty: not trimmed (every other method, ℓ = 0, trim off).
  ImageU8 read;
};
using Masks = std::array<MaskLevel, kLevelCount>;

// A backend's own mask objects (the port: its targets, gpu/masks.h MaskTargets), behind the frame
// contract: the driver hands them from the mask builder to the rule and the shading passes
// without looking inside.
class DeviceMasks {
 public:
  virtual ~DeviceMasks() = default;
};

// What a mask builder hands on (SPEC §3, §9): the backend's own masks, and host images where the
// backend has them: the oracle's always; the port's only when the frame keeps its stages (else
// `host` is empty and the host gets S_ℓ only when it asks, after the frame: RenderOptions::outputs).
struct FrameMasks {
  FrameMasks() = default;
  FrameMasks(Masks h) : host(std::move(h)) {}  // NOLINT: host images alone (the oracle's builders)
  Masks host;
  std::shared_ptr<DeviceMasks> device;
};

// Stencils that are a constant of the frame's size, made on the host for every path:
// mode `full` (level 0 shades exactly the W×H pixels) and uniform-k (S_k = 1 on every level-k
// pixel whose block starts inside W×H; level 0 keeps its G-buffer but shades nothing).
Masks fullModeMasks(const Constants& constants);
Masks uniformMasks(const Constants& constants);

// Stage 5's inputs for one level, and its outputs.
struct LevelImages {
  const ImageF* sub = nullptr;       // c_ℓ (after the bilateral blur)
  const ImageU8* stencil = nullptr;  // S_ℓ
  const ImageF* alpha = nullptr;     // a_ℓ
};

struct BlendResult {
  std::array<ImageF, kLevelCount> upsampled;  // ĉ_ℓ on W×H (empty for disabled levels, or unless kept)
  std::array<ImageF, kLevelCount> alpha;      // α_ℓ on W×H
  std::array<ImageF, kLevelCount> composite;  // c'_ℓ on W×H
  ImageF final;                               // c'_finest
  ImageU8 levelMap;                           // finest level with α > 0 at each pixel

  // W×H final (`channels`) and level map, unfilled: the caller writes every pixel of both.
  // With `keepStages`, also ĉ_ℓ, α_ℓ and c'_ℓ for every enabled level, zero-filled.
  static BlendResult allocate(const Constants& constants, int channels, bool keepStages);
};

struct LevelResult {
  GBuffer gbuffer;   // empty for disabled levels
  MaskLevel masks;   // M_ℓ, a_ℓ, S_ℓ (mrr-effect with τ_v: as refined, SPEC §12.2)
  ImageU8 marks;     // SPEC §12.2: the a-posteriori marks at this level, after the level limit; empty unless refined
  ImageU8 marked;    // SPEC §12.4: the next coarser level's pixels the budget marked for this level (its grid)
  ImageF raw;        // the effect before the bilateral blur
  ImageF sub;        // c_ℓ, after the bilateral blur
  int64_t shadedPixels = 0;       // |S_ℓ|
  int64_t shadedBlockPixels = 0;  // 8 × the 4×2 blocks holding any S_ℓ = 1: what llvmpipe shades
};

// SPEC §12.4: the a-posteriori term's budget at one refined level, and what it spent (the driver
// gives each refined level its prices and, the first, the frame's budget; the backend's selection
// fills the rest, the port once the frame's clock has stopped).
struct RefinementRecord {
  bool budgeted = false;   // selected within a budget (else τ_v alone decided, or nothing was refined)
  int levelsLeft = 0;      // the refined levels from this one down, this one included
  int after = -1;          // the refined level before it (coarser), whose leftover it starts from; −1: none
  double unitNs = 0.0;     // one unit of the budget in ns (budgetUnitNs)
  PixelPrices prices;      // SPEC §11's price of one more level-ℓ pixel by its class, ns
  UnitPrices units;        // the same in units (unitPrices)
  uint32_t leftUnits = 0;  // what was left for this level and the finer ones
  uint32_t shareUnits = 0; // this level's share of it (levelShare)
  uint32_t spentUnits = 0; // the price of the marks taken, S(T)
  uint32_t threshold = 0;  // the selection's priority key T
  int64_t candidates = 0, taken = 0, kept = 0;  // v over its threshold; marked; of those, marked before (§14.2)
  // Each candidate's price in units (level n's grid, row-major), from the a-priori S_ℓ: the
  // selection's input besides v, kept with the stages so that it can be made again on this
  // frame's images (compare, probe).
  std::vector<uint32_t> candidatePrices;
  // SPEC §14.2: the previous frame's selection at this level (its `marked`), where it has one of
  // this level's size: the marks' hysteresis reads it. Empty: none.
  ImageU8 previousMarked;
  double budgetNs() const { return static_cast<double>(shareUnits) * unitNs; }
  double spentNs() const { return static_cast<double>(spentUnits) * unitNs; }
};

struct StageTiming {
  std::string stage;
  double ms = 0.0;
};

// One GL program's draws within one timed stage of the port, each draw timed alone
// (--gpu-timing passes, gpu/pass_clock.h; the report's `passes`).
struct PassTiming {
  std::string stage;     // the timed stage they fell in ("masks", "blend", ...; "" between stages)
  std::string pass;      // the program: the key it was compiled under, its variant included
  std::string shader;    // its fragment shader file
  int calls = 0;
  double ms = 0.0;
};

// What a frame of the port said to the host (gpu/traffic.h, the report's `gl` object;
// docs/port.md, "What a frame costs the host"). Counted where the port makes the calls.
struct GlTraffic {
  bool measured = false;      // false on the oracle, which has no GPU to talk to
  int64_t readbacks = 0;      // images read back (glReadPixels of a target)
  int64_t readbackBytes = 0;  // the bytes of those and of the small reads
  int64_t countReads = 0;     // small reads: a few integers (the never-slower rule's counts)
  int64_t waits = 0;          // the host waiting on the GPU for the frame: glFinish, reads, query results
  int64_t timingWaits = 0;    // ... for the clock alone: the wall clock's glFinish per stage, timer queries
  int64_t finishes = 0;       // glFinish calls, whatever they were for
};

// One rendered frame, as either path fills it. With RenderOptions::keepStages every stage's
// images are here (for --stages, probe and compare); without, the port fills only what the
// report and the outputs need.
struct FrameResult {
  Constants constants;
  Camera camera;  // as given: eye, target, up, vertical field of view
  View view;
  DirectionalLight light;  // the scene's light, as rendered
  ShadowMap shadowMap;     // SSM and SSGI
  ImageU8 shadowLit;       // the one-tap shadow test on the full-res grid (SSM, SSGI)
  ImageU8 pcfSample;       // SSM with the rule: what PCSS pays at each pixel of the 8×8 grid (SPEC §11)
  ImageU8 edgeSample;      // mode mrr with the rule: whether each 8×8 block's diagonal holds an edge (SPEC §11)
  EdgeImages edges;        // on the padded full-res grid (modes mrr and tiles)
  ImageU8 tileRates;       // tiles: each 16×16 tile's level, 0 (1×1), 1 (2×2) or 2 (4×4)
  // SPEC §13 (with --gaze or --prev-frame), on the padded full-res grid: the eccentricity in
  // degrees, the screen motion |v| in full-res pixels, and the level limit (3 channels: what the
  // eye allows, what motion allows, ℓ_min). Empty when the term is off.
  ImageF eccentricity;
  ImageF motion;
  ImageU8 levelLimit;
  FallbackDecision fallback;  // SPEC §11, mode mrr (the predictions also with the rule off)
  FrameCounts counts;         // what the rule counted (mode mrr)
  std::array<RefinementRecord, kLevelCount> refinement;  // SPEC §12.4, mrr-effect with a budget
  // SPEC §12.4's check of the model: each shaded level's predicted time on its final stencil
  // (predictLevelMs; methods under the rule, after the frame's clock), beside its measured stages.
  std::array<double, kLevelCount> predictedLevelMs{};
  std::array<LevelResult, kLevelCount> levels;
  BlendResult blend;  // ĉ_ℓ, α_ℓ, c'_ℓ, final, level map on W×H
  int64_t shadedPixelsTotal = 0;
  double idealSpeedup = 1.0;  // W·H / Σ|S_ℓ| (SPEC §4)
  // The same over pixels that hit geometry, what full mode really pays for (background costs
  // nothing in either mode): hit pixels of W×H / Σ|S_ℓ ∩ hit|, a level pixel (x, y) counting
  // as hit when full-res pixel (x·s + s/2, y·s + s/2) is. countHitPixels sets it.
  double idealSpeedupHit = 1.0;
  // The same over whole 4×2 blocks: llvmpipe skips a block only when all eight fail the
  // stencil (docs/platform.md), so this is the most a stencilled pass can gain there.
  double blockIdealSpeedup = 1.0;
  std::vector<StageTiming> timings;  // in pipeline order; "total" last
  std::vector<PassTiming> passTimings;  // the port with --gpu-timing passes: each program's draws
  // The port (gpu/traffic.h): inside the timed frame; after it (the images and counts the caller
  // asked for, RenderOptions::outputs); and the whole process up to then.
  GlTraffic gl, glAfterFrame, glProcess;
  bool edgeSampled = false;  // the rule's edge sample was taken (f.counts' edgeBlocks, reach are its)

  // SPEC §14, with Constants::temporal on: what the term made from the previous frame (empty
  // without one), and what this frame leaves for the next.
  TemporalImages temporal;
  FrameHistory history;

  ImageF shaded;  // W×H linear RGB for viewing (SPEC §6)

  // The effect buffer: the blend's (SPEC §5), or the temporal term's result where it ran (§14).
  const ImageF& final() const { return temporal.empty() ? blend.final : temporal.result; }
  // idealSpeedupHit, from the stencils and the full-res G-buffer's hit flags (after the frame).
  void countHitPixels(const ImageU8& fullResHit);
  // What stage 5 blends: each level's c_ℓ, S_ℓ and a_ℓ (both paths' blend takes these).
  std::array<LevelImages, kLevelCount> blendInputs() const;
  // |S_ℓ| per level, their sum and the ideal speedup W·H / Σ|S_ℓ| (SPEC §4), from the stencils.
  void countShadedPixels();
  double timing(const std::string& stage) const;
};

// Receives "stage name" as each stage starts (progress lines on stderr).
using ProgressFn = std::function<void(const std::string&)>;

// The host images a frame without keepStages brings back once its clock has stopped (the port;
// the oracle has them anyway). A plain `render` asks only for what it writes; every other
// caller gets them all. The counts (|S_ℓ|, the ideal speedups, the rule's) always come.
enum FrameOutput : unsigned {
  kOutputFinal = 1u << 0,     // the final image and the level map
  kOutputShaded = 1u << 1,    // the shaded image
  kOutputStencils = 1u << 2,  // S_ℓ of every enabled level (f.levels[ℓ].masks.stencil)
  kOutputMaps = 1u << 3,      // SPEC §13's eccentricity, motion and level limit; tiles' rates
  kOutputAll = kOutputFinal | kOutputShaded | kOutputStencils | kOutputMaps,
};

struct RenderOptions {
  // Keep the per-level full-res blend images (ĉ_ℓ, α_ℓ, c'_ℓ) for --stages and probe. The
  // benchmark turns it off: they are debugging output, not part of the method's cost.
  bool keepStages = true;
  ProgressFn progress;
  // The never-slower rule's per-pixel costs (SPEC §11); null: CostModel::defaults of the path.
  const CostModel* costModel = nullptr;
  // Sample what PCSS pays (SSM's pcfSample) and the edges (edgeSample) with the rule off, and
  // with the rule on where its floor already rules the method out, so that f.counts and the
  // report's predictions are the rule's own. `bench --calibrate` and `--rule-sweep` read them from
  // frames rendered with the rule off; a user who turned the rule off does not pay for them.
  bool sampleWithRuleOff = false;
  // SPEC §14: the previous frame of the same camera's path, when it is known (the bench's camera
  // paths, render --prev-frame/--pan, compare): the temporal term reads it. Null: none.
  const FrameHistory* history = nullptr;
  unsigned outputs = kOutputAll;  // FrameOutput bits: what comes back after the frame
  // A caller's own masks (the Python module's masks from numpy, docs/python.md): called once the
  // method's mask builder has made `masks` and before the never-slower rule counts them, with the
  // frame so far (G-buffers, edges, the level limit); it may replace any level's M_ℓ, a_ℓ, S_ℓ.
  // Not called when the rule sent the frame to full resolution before its masks. The oracle shades
  // what it leaves; the port shades the masks it drew, so callers use it with the oracle.
  std::function<void(const FrameResult& f, Masks& masks)> replaceMasks{};
};

// SPEC §11 on a frame whose stencils are `masks` (counted into f.counts) and nothing else of
// the method is paid yet: records both predictions in f.fallback and, when
// f.constants.neverSlower, decides and on a fallback switches f.constants and `masks` to a
// full-res frame. renderFrame calls it at that point for both pipelines.
void applyNeverSlower(FrameResult& f, Masks& masks, const CostModel& model);
// The same decision, leaving the masks to the caller: true when the frame falls back (f.constants
// are then full's; the caller makes full's stencils on its backend).
bool applyNeverSlower(FrameResult& f, const CostModel& model);

// SPEC §11's counts for the frame's stencils: |S_ℓ| and |S_ℓ ∩ hit| per shaded level, from the
// full-res hit flags (a level-ℓ pixel (x, y) is on geometry when full-res pixel (x·s + s/2,
// y·s + s/2) is, clamped to the image: levelPixelHit), into f.counts.
// With `pcfSample` (SSM: what PCSS pays at each pixel of the kPcfSampleStep grid, pcfSample in
// cpu_ref/ssm.h; empty otherwise) also |S_ℓ ∩ hit ∩ pcf| and |S_ℓ ∩ hit ∩ searched|, a full-res
// pixel on geometry paying what the sample of its kPcfSampleStep² block pays; without it every
// pixel on geometry counts as searched. H, H_a and H_p are countHits' (the frame counts them
// once, before its early decision).
void countForRule(FrameCounts& counts, const Masks& masks, const Constants& constants, const ImageU8& fullResHit,
                  const ImageU8& pcfSample);
// H, H_a and H_p: the full-res pixels on geometry, those of them that pay the effect's per-pixel
// cost (SSM: its blocker search; every one without a sample) and those that pay PCF.
// `silhouetteBlocks`, if given: the 8×8 blocks (the coarsest level's) that hold a silhouette pixel.
void countHits(FrameCounts& counts, const ImageU8& fullResHit, const ImageU8& pcfSample, const Constants& constants,
               ImageU8* silhouetteBlocks = nullptr);
// SPEC §11's edge sample, counted: the blocks (kEdgeSampleStep² full-res pixels each) of
// `edgeSample` or of `silhouetteBlocks` (countHits'), |Ê| (counts.edgeBlocks); then for each
// shaded level ℓ below the coarsest, the blocks within r_ℓ of one, with every finer level's (the
// masks' closure), as level-ℓ pixels (counts.reach) and the full-res pixels on geometry they
// hold (counts.reachHits).
void countEdgeSample(FrameCounts& counts, const ImageU8& edgeSample, const ImageU8& silhouetteBlocks,
                     const ImageU8& fullResHit, const Constants& constants);
// Blocks of a 0/1 block map, each blockSize² pixels of some level, within `radius` pixels
// (across; radiusY down) of a set block's pixels: dilated by ceil(radius / blockSize) blocks,
// a separable box max. Where a blur of radius r of what the set blocks hold can be non-zero
// (gpu/masks.cpp draws its passes there; the rule's edge sample estimates S_ℓ's reach with it).
ImageU8 nearBlocks(const ImageU8& blocks, int blockSize, int radius, int radiusY = -1);  // radiusY < 0: radius
// The sample's byte (its class kPcfSample… and footprint, common/shader_constants.h) for full-res
// pixel (x, y): that of its kPcfSampleStep² block.
inline uint8_t pcfSampleValue(const ImageU8& pcfSample, int x, int y) {
  return pcfSample.at(std::min(x / kPcfSampleStep, pcfSample.width - 1),
                      std::min(y / kPcfSampleStep, pcfSample.height - 1));
}
// SPEC §0: the full-res pixel that level pixel x (of scale s) samples, along one axis: x·s + ⌊s/2⌋,
// a pixel at its block's centre (level 0: the pixel itself). Level ℓ's G-buffer is level 0's at
// these pixels (§1: subsampleGBuffer), and the blend puts its values there (§5).
inline int levelSamplePixel(int x, int scale) { return x * scale + scale / 2; }
// The level pixels, along one axis, whose s_ℓ×s_ℓ block starts inside the image's fullExtent
// pixels: the ones a full-res pixel falls in (the peers' and full's shaded extent, SPEC §9).
inline int levelExtent(int fullExtent, int scale) { return (fullExtent + scale - 1) / scale; }
// SPEC §0: the level texel whose sample is nearest an on-screen point at level coordinates
// u = q/s (q a continuous full-res coordinate, u in [0, level size)), along one axis: the samples
// sit at x·s + ⌊s/2⌋ + ½, half a full-res pixel past their blocks' centres above level 0, so
// floor(u − ½/s) there (clamped at 0) and floor(u) at level 0. SSAO's occluders and SSGI's
// senders are looked up here (ssao.frag and ssgi.frag take the same steps).
inline int nearestLevelTexel(float u, float invScale) {
  const float shifted = invScale < 1.0f ? u - 0.5f * invScale : u;
  return std::max(static_cast<int>(std::floor(shifted)), 0);
}
inline bool levelPixelHit(const ImageU8& fullResHit, int x, int y, int scale) {
  return fullResHit.at(std::min(levelSamplePixel(x, scale), fullResHit.width - 1),
                       std::min(levelSamplePixel(y, scale), fullResHit.height - 1)) != 0;
}

// SPEC §13. The level-limit image's channels (step 5): what the eye allows, what motion allows,
// and the limit ℓ_min, each a level index (cpu_ref/foveation.h makes it; gpu/shaders/limit.frag).
enum LimitChannel { kLimitFovea = 0, kLimitMotion = 1, kLimitLevel = 2, kLimitChannels = 3 };
// The previous frame's view (same size and padding as this frame's), from Constants::Foveation.
// With --pan, the current view `current` with its eye moved by −pan along its right axis.
View previousView(const Constants& c, const View& current);
// Step 6 for tiles (SPEC §9): a tile's rate is max(its content rate, min(2, ℓ_min at its centre
// pixel (16 t + 8), clamped to the grid)), as VRS combines a foveation rate with a content rate.
// Both paths' tile rates are host images, so both call this.
void limitTileRates(ImageU8& rates, const ImageU8& limit);

// The bytes one rendered FrameResult holds (every level's G-buffer, masks, raw and blurred
// sub-images and per-effect scratch; the full-res edges, blend, level map and shaded image;
// the shadow map), plus the full-res images written out. An estimate made from the sizes
// alone, before anything is allocated: the memory check up front (common/memory.h).
int64_t estimateFrameBytes(const Constants& constants, bool keepStages);

}  // namespace mrr
