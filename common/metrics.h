#pragma once
// Error figures of SPEC §10, on float images with any number of channels, each computed
// against a reference of the same size. Reductions run in double, row by row and then in
// a fixed order, so the figures are identical for any thread count.
#include <cstdint>

#include "common/image.h"

namespace mrr {

struct ErrorFigures {
  double rms = 0.0;           // sqrt(mean over pixels and channels of Δ²): the paper's figure
  double psnr = 0.0;          // 10·log10(1 / mean Δ²), data range 1; +inf when identical
  double ssim = 1.0;          // Wang et al. 2004, 11×11 Gaussian σ=1.5, K1=0.01, K2=0.03, range 1,
                              // mean over the valid window positions, channels averaged
  double maxAbs = 0.0;        // max |Δ|
  double edgeBandRms = 0.0;   // RMS over pixels within 4 px of a mask transition
  int64_t edgeBandPixels = 0; // how many pixels that band holds
};

double rmsError(const ImageF& test, const ImageF& ref);
double maxAbsError(const ImageF& test, const ImageF& ref);
double psnr(const ImageF& test, const ImageF& ref);
double ssim(const ImageF& test, const ImageF& ref);

// Pixels within `radius` (Chebyshev distance, full-res pixels) of a transition in `labels`,
// i.e. of a pixel whose 4-neighbour has a different label.
ImageU8 transitionBand(const ImageU8& labels, int radius = 4);

// RMS over the pixels where `band` is non-zero (0 if the band is empty).
double maskedRms(const ImageF& test, const ImageF& ref, const ImageU8& band);

// All figures at once; `labels` is the per-pixel finest contributing level (pipeline output).
ErrorFigures compareToReference(const ImageF& test, const ImageF& ref, const ImageU8& labels);

}  // namespace mrr
