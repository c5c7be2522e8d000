#pragma once
// Whether a frame's effect is constant over its surface: an SSGI frame whose light
// reaches nothing the view sees is black everywhere, and a comparison of two black frames
// passes while checking nothing. `compare` warns on such a frame and suggests --light-dir.
#include "common/frame.h"

namespace mrr {

// The effect's range over the frame's surface pixels (the full-res G-buffer's hits inside W×H).
struct EffectRange {
  int64_t surfacePixels = 0;
  float lo = 0.0f, hi = 0.0f;  // the smallest and largest value of any channel there
  double mean = 0.0;           // over the channels and the surface pixels
};
EffectRange effectRange(const FrameResult& frame);

// The effect varies by less than kConstantEffectRange over the surface (or the view sees none).
inline constexpr float kConstantEffectRange = 1e-3f;
bool effectIsConstant(const FrameResult& frame);

}  // namespace mrr
