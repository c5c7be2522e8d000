#pragma once
// LDR-FLIP: the perceptual difference of Andersson et al. 2020, "FLIP: A Difference Evaluator
// for Alternating Images" (HPG; Proc. ACM CGIT 3(2)), written from the paper.
//
// Two images seen as a viewer sees them, as sRGB values in [0,1], give a per-pixel error in
// [0,1]: a colour pipeline (opponent space YyCxCz, contrast-sensitivity filters, CIELAB with
// the Hunt adjustment, HyAB distance, compressed and remapped) and a feature pipeline (edges
// and points of the achromatic channel, found by the first and second derivatives of a
// Gaussian) are combined per pixel as ΔE = ΔE_c^(1 − ΔE_f).
//
// Every filter is separable and runs row by row through parallelFor (common/parallel.h);
// each pixel's arithmetic does not depend on which thread ran it and the statistics reduce
// in a fixed order, so the map and the figures are identical for any thread count.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <numbers>
#include <string>

#include "common/image.h"

namespace mrr {

// Viewing conditions: pixels per degree of visual angle. The default is a 0.7 m
// wide 3840-pixel display seen from 0.7 m: 0.7 · 3840 / 0.7 · π/180 ≈ 67.02, the reference
// implementation's default ("67" in its documentation).
inline constexpr double kFlipDefaultPpd = 0.7 * 3840.0 / 0.7 * std::numbers::pi / 180.0;

// The paper's constants, named as there.
struct FlipConstants {
  // Contrast sensitivity in the spatial domain, per opponent channel:
  // S(x) = a1·sqrt(π/b1)·exp(−π²x²/b1) + a2·sqrt(π/b2)·exp(−π²x²/b2), x in degrees.
  double a1[3] = {1.0, 1.0, 34.1};       // achromatic, red–green, blue–yellow
  double b1[3] = {0.0047, 0.0053, 0.04};
  double a2[3] = {0.0, 0.0, 13.5};
  double b2[3] = {1e-5, 1e-5, 0.025};
  double qc = 0.7;    // colour-error compression exponent
  double pc = 0.4;    // fraction of the largest colour error where the remapping bends
  double pt = 0.95;   // the error it bends to
  double w = 0.082;   // feature width, degrees: σ = w/2 · ppd pixels
  double qf = 0.5;    // feature-error exponent
};

// Figures of an error map: mean over every pixel, median and quartiles (linear interpolation
// between order statistics, as numpy.percentile), and max.
struct FlipStats {
  double mean = 0.0;
  double median = 0.0;
  double q1 = 0.0;
  double q3 = 0.0;
  double max = 0.0;
};
// As JSON: {"mean", "median", "q1", "q3", "max"} (`mrr diff --json`, the reports' "flip").
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FlipStats, mean, median, q1, q3, max)

struct FlipResult {
  ImageF errorMap;  // one channel, [0,1]
  FlipStats stats;
};

// LDR-FLIP of `test` against `reference`, both W×H with 1 channel (grey) or 3 or more (the
// first three are R, G, B), holding sRGB-encoded display values; values outside [0,1] are
// clamped. Throws MrrError when the sizes differ.
FlipResult flip(const ImageF& reference, const ImageF& test, double ppd = kFlipDefaultPpd);

FlipStats flipStats(const ImageF& errorMap);

// The display values of a linear image, as `--shaded x.png` writes it: clamped to [0,1] and
// sRGB-encoded (the shaded image).
ImageF linearToDisplay(const ImageF& linear);

// An error map in [0,1] as sRGB display values (bytes / 255, for writeImage's PNG) through the magma colour map (0 black, 1 pale yellow),
// as the paper shows its maps. With `legend`, a colour bar from 0 (left) to 1 (right), with
// ticks at each 0.1, is added below the map.
ImageF flipColourMap(const ImageF& errorMap, bool legend = false);

// The same colours as 8-bit RGB, no legend (the compare page's and explore's FLIP maps), one
// value's colour, and the scale as a CSS gradient from 0 (left) to 1 (right) for their legends.
ImageU8 flipColourMapBytes(const ImageF& errorMap);
void flipMagma(float v, uint8_t* rgb);
std::string flipMagmaGradient();

}  // namespace mrr
