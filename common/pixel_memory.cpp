#include "common/pixel_memory.h"

#include <sys/mman.h>
#include <tbb/scalable_allocator.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>
#include <thread>

namespace mrr {

namespace {

constexpr size_t kHugePage = size_t{2} << 20;
std::atomic<size_t> gRawBytes{0};

#ifndef MRR_SANITIZED  // the sanitizers' builds take images from malloc
// The reserved region (PixelReservation): raw requests are cut from its front while it lasts.
std::atomic<uintptr_t> gReservedNext{0};
uintptr_t gReservedEnd = 0;

void* mapHugeAligned(size_t bytes) {
  const size_t mapped = bytes + kHugePage;
  void* m = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (m == MAP_FAILED) return nullptr;
  const auto base = reinterpret_cast<uintptr_t>(m);
  const uintptr_t aligned = (base + kHugePage - 1) / kHugePage * kHugePage;
  if (aligned > base) munmap(m, aligned - base);
  if (const uintptr_t end = base + mapped, used = aligned + bytes; end > used)
    munmap(reinterpret_cast<void*>(used), end - used);
  madvise(reinterpret_cast<void*>(aligned), bytes, MADV_HUGEPAGE);  // a hint: ignored where THP is off
  return reinterpret_cast<void*>(aligned);
}

// The pool's raw memory: whole 2 MiB pages, 2 MiB-aligned, advised as huge pages (a hint,
// ignored where THP is off). Mapped with room to align, the ends trimmed.
void* rawAlloc(intptr_t /*pool*/, size_t& bytes) {
  bytes = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  for (uintptr_t at = gReservedNext.load(); at && at + bytes <= gReservedEnd;)
    if (gReservedNext.compare_exchange_weak(at, at + bytes)) {
      gRawBytes += bytes;
      return reinterpret_cast<void*>(at);
    }
  void* p = mapHugeAligned(bytes);
  if (p) gRawBytes += bytes;
  return p;
}

// Called at the pool's destruction only (keepAllMemory), which never comes.
int rawFree(intptr_t /*pool*/, void* /*p*/, size_t /*bytes*/) { return 0; }

rml::MemoryPool* pool() {
  // Never destroyed: images in static storage may outlive any destruction order.
  static rml::MemoryPool* const p = [] {
    rml::MemoryPool* created = nullptr;
    const rml::MemPoolPolicy policy(rawAlloc, rawFree, kHugePage, /*fixedPool=*/false, /*keepAllMemory=*/true);
    if (rml::pool_create_v1(0, &policy, &created) != rml::POOL_OK) created = nullptr;
    return created;
  }();
  return p;
}
#endif

}  // namespace

void* allocatePixels(size_t bytes) {
  void* p = nullptr;
#ifndef MRR_SANITIZED
  if (rml::MemoryPool* mp = pool()) p = rml::pool_aligned_malloc(mp, bytes, 64);
#else
  p = std::malloc(bytes);
#endif
  if (!p) throw std::bad_alloc();
  return p;
}

void freePixels(void* p, size_t /*bytes*/) noexcept {
#ifndef MRR_SANITIZED
  if (rml::MemoryPool* mp = pool()) rml::pool_free(mp, p);
#else
  std::free(p);
#endif
}

struct PixelReservation::Worker {
  std::thread thread;
};

PixelReservation::PixelReservation(size_t bytes) {
#ifndef MRR_SANITIZED
  // The pool holds more than the images' bytes: its raw requests come in whole 2 MiB pages,
  // and it keeps its own blocks' headers (720p SSAO-64 mrr: 128 MiB held for a 114 MiB
  // estimate). A quarter more covers it.
  bytes += bytes / 4;
  bytes = (bytes + kHugePage - 1) / kHugePage * kHugePage;
  if (bytes == 0 || gReservedNext.load() != 0) return;  // one reservation per process
  void* region = mapHugeAligned(bytes);
  if (!region) return;
  bytes_ = bytes;
  gReservedEnd = reinterpret_cast<uintptr_t>(region) + bytes;
  gReservedNext.store(reinterpret_cast<uintptr_t>(region));
#ifdef MADV_POPULATE_WRITE
  worker_ = new Worker{std::thread([region, bytes] {
    constexpr size_t kStep = size_t{16} << 20;  // in steps, so that a frame starting early is not held up
    for (size_t at = 0; at < bytes; at += kStep)
      if (madvise(static_cast<char*>(region) + at, std::min(kStep, bytes - at), MADV_POPULATE_WRITE) != 0) break;
  })};
#endif
#else
  (void)bytes;
#endif
}

void PixelReservation::wait() {
  if (worker_ && worker_->thread.joinable()) worker_->thread.join();
}

PixelReservation::~PixelReservation() {
  wait();
  delete worker_;
}

size_t pixelPoolBytes() { return gRawBytes.load(); }

}  // namespace mrr
