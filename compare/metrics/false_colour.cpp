#include "compare/metrics/false_colour.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "common/error.h"

namespace mrr {

namespace {

constexpr std::array<std::array<int, 3>, 9> kRamp = {{{0, 0, 4},
                                                      {31, 12, 72},
                                                      {85, 15, 109},
                                                      {136, 34, 106},
                                                      {186, 54, 85},
                                                      {227, 89, 51},
                                                      {249, 140, 10},
                                                      {249, 201, 50},
                                                      {252, 255, 164}}};

}  // namespace

void rampColour(double t, uint8_t rgb[3]) {
  t = std::isnan(t) ? 1.0 : std::clamp(t, 0.0, 1.0);
  const double s = t * static_cast<double>(kRamp.size() - 1);
  const size_t i = std::min(static_cast<size_t>(s), kRamp.size() - 2);
  const double f = s - static_cast<double>(i);
  for (size_t c = 0; c < 3; ++c) {
    const double v = (1.0 - f) * kRamp[i][c] + f * kRamp[i + 1][c];
    rgb[c] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
}

ImageU8 heatMap(const ImageF& delta, double scale) {
  ImageU8 out(delta.width, delta.height, 3, 0);
  for (size_t p = 0; p < delta.pixelCount(); ++p) {
    const double d = delta.data[p];
    if (!(d > 0.0) && !std::isnan(d)) continue;  // exactly 0: black
    const double t = std::isfinite(d) && scale > 0.0 ? d / scale : 1.0;
    rampColour(t, &out.data[p * 3]);
  }
  return out;
}

std::string rampGradient() {
  std::string css = "linear-gradient(to right";
  for (const auto& c : kRamp)
    css += ",rgb(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + ")";
  return css + ")";
}

std::string encodePng(const ImageU8& image) {
  require(!image.empty(), "encodePng: an empty image");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  auto out = OIIO::ImageOutput::create("png");
  require(out != nullptr, "PNG encoding: no PNG writer in OpenImageIO");
  OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
  spec.attribute("png:compressionLevel", 3);  // fast: the page asks for images as it is used
  out->set_ioproxy(&proxy);
  require(out->open("explore.png", spec) && out->write_image(OIIO::TypeDesc::UINT8, image.data.data()) && out->close(),
          "PNG encoding: " + out->geterror());
  return std::string(bytes.begin(), bytes.end());
}

}  // namespace mrr
