#pragma once
// Counts summed on the GPU (gpu/shaders/counts.frag) and read as a few integers: what the
// never-slower rule decides on and what the report says of a frame (|S_ℓ|, the ideal speedups),
// without an image coming back (docs/port.md, "What a frame costs the host"). A pass writes a few
// counts per block into RGBA32UI targets (gpu/rule.h); a batch sums each target down to one
// texel and reads them all in one small read (gpu/traffic.h readCounts).
#include <cstdint>
#include <vector>

#include "gpu/gbuffer.h"

namespace mrr::gpu {

class CountBatch {
 public:
  explicit CountBatch(const GpuScene& scene) : scene_(scene) {}
  // Queues the sums of every target of `perBlock` (RGBA32UI; the batch keeps it until read);
  // returns the index of its first target's sums in read()'s values (4 per target, in the
  // targets' order). At most kMaxTargets targets a batch.
  size_t add(Target perBlock);
  // The sums: targets of one size reduced together (one pass per step of 16×16, up to 8 targets a
  // pass), then one gather pass and one small read: 4 sums per queued target, in the order added.
  std::vector<int64_t> read();
  // The i-th target the last read() summed, back to the caller (its images as they were).
  Target take(size_t i);
  static constexpr int kMaxTargets = 8;

 private:
  const GpuScene& scene_;
  std::vector<Target> kept_;  // the queued targets, alive until read()
  std::vector<Target> summed_;  // what the last read() summed, for take()
};

}  // namespace mrr::gpu
