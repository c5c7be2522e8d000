#include "compare/parity/constant_effect.h"

#include <algorithm>
#include <limits>

namespace mrr {

EffectRange effectRange(const FrameResult& frame) {
  EffectRange out;
  const ImageF& f = frame.final();
  const GBuffer& g = frame.levels[0].gbuffer;  // the padded full-res grid: W×H is its top-left
  out.lo = std::numeric_limits<float>::infinity();
  out.hi = -out.lo;
  double sum = 0.0;
  for (int y = 0; y < f.height && y < g.height; ++y)
    for (int x = 0; x < f.width && x < g.width; ++x) {
      if (!g.hit.at(x, y)) continue;
      ++out.surfacePixels;
      for (int c = 0; c < f.channels; ++c) {
        const float v = f.at(x, y, c);
        out.lo = std::min(out.lo, v);
        out.hi = std::max(out.hi, v);
        sum += v;
      }
    }
  if (out.surfacePixels == 0) {
    out.lo = out.hi = 0.0f;
    return out;
  }
  out.mean = sum / (static_cast<double>(out.surfacePixels) * f.channels);
  return out;
}

bool effectIsConstant(const FrameResult& frame) {
  const EffectRange r = effectRange(frame);
  return r.surfacePixels == 0 || !(r.hi - r.lo >= kConstantEffectRange);
}

}  // namespace mrr
