#pragma once
// Showing non-colour data: the false-colour ramp that the compare report's heat maps and
// `mrr explore`'s layers share (one ramp, one legend), and PNG encoding in memory.
#include <string>

#include "common/image.h"

namespace mrr {

// The ramp's colour at t in [0, 1] (inferno-like, from black: perceptually ordered, readable
// in grey); out-of-range t is clamped.
void rampColour(double t, uint8_t rgb[3]);

// |Δ| per pixel as the ramp: 0 black, `scale` and above (and NaN) the ramp's top.
ImageU8 heatMap(const ImageF& delta, double scale);

// The ramp as a CSS linear-gradient, for a legend.
std::string rampGradient();

// An 8-bit image (1, 3 or 4 channels) as PNG bytes, through OpenImageIO. Throws MrrError.
std::string encodePng(const ImageU8& image);

}  // namespace mrr
