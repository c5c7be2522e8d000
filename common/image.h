#pragma once
// A plain row-major image with interleaved channels. Every stage of both paths reads and
// writes these, so the oracle, the port's readback and the comparison share one layout.
#include "common/parallel.h"
#include "common/pixel_memory.h"

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <new>
#include <cstdint>
#include <memory>
#include <vector>

namespace mrr {

// An allocator that leaves elements uninitialised on resize, so that a new image can be
// filled in parallel: first touch of a large image is page faults, and a serial memset puts
// them all on one core (it was a fifth of a 1080p frame). Images of 64 KiB and more take their
// pixels from the huge-page pool of common/pixel_memory.h, which keeps them for the next image.
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  using std::allocator<T>::allocator;

  T* allocate(size_t n) {
    if (n * sizeof(T) < kPooledPixelBytes) return std::allocator<T>::allocate(n);
    return static_cast<T*>(allocatePixels(n * sizeof(T)));
  }
  void deallocate(T* p, size_t n) {
    if (n * sizeof(T) < kPooledPixelBytes) return std::allocator<T>::deallocate(p, n);
    freePixels(p, n * sizeof(T));
  }
  template <class U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using PixelVector = std::vector<T, DefaultInitAllocator<T>>;

template <class T>
struct Image {
  int width = 0;
  int height = 0;
  int channels = 1;
  PixelVector<T> data;

  Image() = default;
  Image(int w, int h, int c = 1, T fill = T{}) : width(w), height(h), channels(c) {
    data.resize(static_cast<size_t>(w) * h * c);
    constexpr size_t kChunk = size_t{1} << 16;
    parallelFor(size_t{0}, (data.size() + kChunk - 1) / kChunk, [&](size_t chunk) {
      const size_t end = std::min(data.size(), (chunk + 1) * kChunk);
      for (size_t i = chunk * kChunk; i < end; ++i) data[i] = fill;
    });
  }

  // An image whose pixels the caller writes, every one, before anything reads them: no fill
  // pass (for stages that produce a whole image, where the fill was a fifth of their time).
  static Image uninitialised(int w, int h, int c = 1) {
    Image img;
    img.width = w;
    img.height = h;
    img.channels = c;
    img.data.resize(static_cast<size_t>(w) * h * c);
    return img;
  }

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
