#pragma once
// A plain row-major image with interleaved channels. Every stage of both paths reads and
// writes these, so the oracle, the port's readback and the comparison share one layout.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mrr {

template <class T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<T> data;

  Image() = default;
  Image(int w, int h, int c = 1, T fill = T{})
      : width(w), height(h), channels(c), data(static_cast<size_t>(w) * h * c, fill) {}

  size_t index(int x, int y, int c = 0) const {
    return (static_cast<size_t>(y) * width + x) * channels + c;
  }
  T& at(int x, int y, int c = 0) { return data[index(x, y, c)]; }
  const T& at(int x, int y, int c = 0) const { return data[index(x, y, c)]; }
  bool empty() const { return data.empty(); }
  size_t pixelCount() const { return static_cast<size_t>(width) * height; }
  bool contains(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

using ImageF = Image<float>;
using ImageU8 = Image<uint8_t>;

// The top-left w×h window of `src` (used to crop padded grids back to W×H, SPEC §0).
template <class T>
Image<T> crop(const Image<T>& src, int w, int h) {
  Image<T> out(w, h, src.channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < src.channels; ++c) out.at(x, y, c) = src.at(x, y, c);
  return out;
}

// Converts a 0/1 byte image to float, for writing and comparing.
inline ImageF toFloat(const ImageU8& src) {
  ImageF out(src.width, src.height, src.channels);
  for (size_t i = 0; i < src.data.size(); ++i) out.data[i] = static_cast<float>(src.data[i]);
  return out;
}

}  // namespace mrr
