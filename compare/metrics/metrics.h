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
double meanAbsError(const ImageF& test, const ImageF& ref);  // mean |Δ| over pixels and channels
double psnr(const ImageF& test, const ImageF& ref);
double ssim(const ImageF& test, const ImageF& ref);

// Pixels within `radius` (Chebyshev distance, full-res pixels) of a transition in `labels`,
// i.e. of a pixel whose 4-neighbour has a different label.
ImageU8 transitionBand(const ImageU8& labels, int radius = 4);

// RMS over the pixels where `band` is non-zero (0 if the band is empty).
double maskedRms(const ImageF& test, const ImageF& ref, const ImageU8& band);

// All figures at once; `labels` is the per-pixel finest contributing level (pipeline output).
ErrorFigures compareToReference(const ImageF& test, const ImageF& ref, const ImageU8& labels);

// Temporal stability along a camera path (SPEC §10): flicker = mean over t ≥ 1 and every
// pixel and channel of |(X_t − R_t) − (X_{t−1} − R_{t−1})|, the frame-to-frame change of the
// error against the reference R; 0 when a method's error is steady, whatever the scene does.
// Frames are added in path order; only the previous frame's error is kept.
//
// Beside it, the same for the perceptual error: with F_t the LDR-FLIP map of X_t
// against R_t (compare/metrics/flip.h; the frames as display values, clamped to [0,1], one channel as
// grey), FLIP flicker = mean over t ≥ 1 and every pixel of |F_t − F_{t−1}|. FLIP has no sign,
// so an error that only changes sign is steady here; an error that comes and goes is not.
class FlickerMeter {
 public:
  // `withFlip` false: flicker and mean RMS only, no FLIP map a frame (flipFlicker and meanFlip 0)
  explicit FlickerMeter(bool withFlip = true) : withFlip_(withFlip) {}
  void add(const ImageF& test, const ImageF& ref);
  double flicker() const;          // 0 before two frames
  int frames() const { return frames_; }
  double meanRms() const;          // the mean per-frame RMS against R, for the same table
  double flipFlicker() const;      // 0 before two frames
  double meanFlip() const;         // the mean per-frame mean FLIP against R

 private:
  ImageF previousError_, previousFlip_;
  double sum_ = 0.0, rmsSum_ = 0.0, flipSum_ = 0.0, flipMeanSum_ = 0.0;
  int64_t count_ = 0, flipCount_ = 0;
  int frames_ = 0;
  bool withFlip_ = true;
};

}  // namespace mrr
