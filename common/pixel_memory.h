#pragma once
// Where images keep their pixels (a single cold frame as fast as a warm one).
//
// A frame allocates a few hundred MB of images, and on a fresh process every page of them is a
// page fault on first touch. In a VM a 4 KiB fault costs ~10 µs: at 1280×720 SSAO-64 a cold
// `mrr render` spent ~0.34 s of system time in 26,000 faults, and lost a quarter of the warm
// speedup (mrr pays more of them than full: its coarse levels, masks and blend images).
//
// So every image of 64 KiB or more comes from one process-wide TBB memory pool (rml, the
// scalable allocator's pools) whose raw memory is 2 MiB-aligned regions advised as
// transparent huge pages: 512× fewer faults where the kernel offers THP (madvise mode, as on
// Debian), and the pool keeps freed images' memory for the next image of the same or the next
// frame, so pages are touched once per process. Sanitized builds use malloc (MRR_SANITIZED),
// which the sanitizers watch.
#include <cstddef>
#include <cstdint>

namespace mrr {

inline constexpr size_t kPooledPixelBytes = size_t{64} << 10;  // smaller images: malloc

void* allocatePixels(size_t bytes);            // throws std::bad_alloc
void freePixels(void* p, size_t bytes) noexcept;

// A frame's pages, faulted in ahead on a spare core ("touch pages once"). Maps
// `bytes` (the frame's estimate; the pool's headroom is added here) for the pool, huge-page
// advised, and populates them on a thread of its own (MADV_POPULATE_WRITE: mapped and zeroed,
// contents untouched, so the pool may already hand them out) while the caller loads its scene; the pool's raw requests are served from it
// first. wait() joins the thread; the destructor too. Without MADV_POPULATE_WRITE (Linux <
// 5.14) the region is simply the pool's first memory.
class PixelReservation {
 public:
  explicit PixelReservation(size_t bytes);
  PixelReservation(const PixelReservation&) = delete;
  PixelReservation& operator=(const PixelReservation&) = delete;
  ~PixelReservation();
  void wait();
  size_t bytes() const { return bytes_; }

 private:
  size_t bytes_ = 0;
  struct Worker;
  Worker* worker_ = nullptr;
};

// Raw memory the pool has taken from the kernel so far, in bytes (for reports and tests).
size_t pixelPoolBytes();

}  // namespace mrr
