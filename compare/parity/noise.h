#pragma once
// The noise-aware verdict (`mrr compare --noise-aware`, docs/spec.md §8). SSAO's and
// SSGI's effect is a Monte Carlo estimate: a renderer with its own sampling (another --seed, blue
// noise, another kernel) draws another sample of the same estimator and cannot match the oracle
// pixel for pixel. For the stochastic stages (raw.Lℓ, and sub.Lℓ, final, shaded downstream) the
// oracle renders K frames with independent seeds (kNoiseRule, common/tolerance.h); the subject's
// stage is then judged by the statistics of compare/metrics/noise_stats.h:
//   - per pixel, Welch's t of the subject's value against the K seeds' mean, the subject's own
//     spread taken as the seeds' (the same estimator at the same sample count), with Šidák's
//     family-wise correction over every pixel and channel: a local bug;
//   - over the frame and its regions (the edge band, each level's stencil), the relative bias of
//     the subject's sum against the spread of the seeds' own biases: a shift of a few per cent
//     no single pixel shows.
// The deterministic stages, and the same-input checks downstream (the bilateral blur and the blend
// of the subject's own images), keep their exact rules.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/frame.h"
#include "compare/metrics/noise_stats.h"
#include "compare/parity/parity.h"

namespace mrr {

// The oracle's stochastic stages over K seeds: "raw.L0" → K images, in the stage's own grid.
struct NoiseReference {
  int seeds = 0;
  int samples = 0;  // N, per pixel
  std::map<std::string, std::vector<ImageF>> stages;
};

// Renders the oracle K times (`render(seed)` with kNoiseRule's seeds) and keeps the stochastic
// stages. `progress(k, K)` is called before each frame.
NoiseReference buildNoiseReference(const std::function<FrameResult(uint32_t seed)>& render, int samples,
                                   const std::function<void(int, int)>& progress = {});

// A region of the stage's grid: its name and the pixels in it.
struct NoiseRegion {
  std::string name;
  std::vector<char> mask;
};

// The noise test of one stage image: the subject against the K seeds' images over the pixels
// `include` picks; the bias over every region (the first is normally "frame", all included).
NoiseFigures noiseTest(const ImageF& subject, const std::vector<ImageF>& seeds, const std::vector<char>& include,
                       const std::vector<NoiseRegion>& regions, int samples);

// Replaces, in `result`, the end-to-end checks of the stochastic stages by the noise test
// against `reference` (the raw.Lℓ rows also drop their same-input check, which assumes mrr's own
// sampling); every other check is kept. `oracle`: the oracle's frame at seed 0 (its stencils,
// masks, edges and level map give the regions); `subject`: the port's frame or the file's.
void applyNoiseAware(ParityResult& result, const FrameResult& oracle, const FrameResult& subject,
                     const NoiseReference& reference);

// One channel of one stochastic stage at one pixel (`probe --noise-aware`, explore's probe panel).
struct NoiseChannel {
  double value = 0.0;                // the subject's
  double mean = 0.0;                 // the K seeds' mean
  double meanLo = 0.0, meanHi = 0.0; // the mean's own t interval at 95% (where the estimator's mean lies)
  double sd = 0.0;                   // one draw's spread: the seeds' standard deviation, at least kNoiseRule.sampleFloor samples' worth
  double lo = 0.0, hi = 0.0;         // the interval the verdict accepts one draw in: Welch's t at the stage's Šidák level
  double t = 0.0, p = 1.0;           // the subject's Welch t against the mean, and its two-sided p
  double halfWidths = 0.0;           // |value − mean| in half-widths of [lo, hi]: ≤ 1 inside
  bool inside = true;
};

// One stochastic stage at one pixel.
struct NoisePixelStage {
  std::string stage;   // "raw.L0", "sub.L2", "final", "shaded"
  std::string shader;  // the port's shader that computes it
  int level = -1;      // -1: a full-res stage
  int x = 0, y = 0;    // the pixel in the stage's own grid
  bool shaded = true;  // false: the level's stencil leaves this pixel to another level (no estimate here)
  int64_t stagePixels = 0;  // the pixels the verdict tests on this stage (the Šidák family, × channels)
  double pixelLevel = 0.0;  // the per-test level the verdict uses: Šidák over stagePixels × channels
  int farthest = 0;         // the channel farthest from its mean, in half-widths
  std::vector<NoiseChannel> channels;
};

// Each stochastic stage at full-res pixel (x, y): the subject's value against the K seeds.
struct NoisePixel {
  int x = 0, y = 0;
  int seeds = 0, samples = 0;
  uint32_t firstSeed = 0;
  std::vector<NoisePixelStage> stages;
  bool inside() const;  // every shaded stage's every channel inside its accepted interval
};

NoisePixel noisePixel(const FrameResult& oracle, const FrameResult& subject, const NoiseReference& reference, int x, int y);

// `mrr probe --path both --noise-aware`: the story of one pixel's stochastic stages, a line a stage
// (the seeds' mean ± its 95% interval, one draw's spread, the interval the verdict accepts, the
// subject's value and where it falls in it), then a verdict. `whose`: "the file's", "the port's".
std::string formatNoisePixel(const NoisePixel& pixel, const std::string& whose);

// The same as JSON (probe --json --noise-aware, explore's /api/noise).
nlohmann::json noisePixelJson(const NoisePixel& pixel);

}  // namespace mrr
