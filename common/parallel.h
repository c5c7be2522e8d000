#pragma once
// Every parallel loop of the oracle goes through parallelFor, with tbb::parallel_for's
// overloads and contract (a Range with TBB's splitting constructor, or first/last/f).
//
// In a ThreadSanitizer build (scripts/test-sanitizers.sh) the loops run on std::threads
// instead: Debian's libtbb is not built with TSan, so the hand-off of a range to a worker
// inside its scheduler is invisible to TSan and every loop would be reported. Here the
// range is split the way TBB splits it (the same splitting constructor, down to its grain),
// and max_allowed_parallelism threads — the count tbb::global_control sets, so the 1-, 2-
// and 8-thread tests mean what they say — take pieces from a shared counter. Thread start
// and join are what TSan understands, so every report left is a real race between two
// pieces of one loop: the kind of bug this build exists to find.
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#if defined(__SANITIZE_THREAD__)
#define MRR_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define MRR_TSAN 1
#endif
#endif

#ifdef MRR_TSAN
#include <atomic>
#include <thread>
#include <vector>
#endif

namespace mrr {

#ifdef MRR_TSAN
template <class Range, class Body>
void parallelForOnThreads(const Range& range, const Body& body) {
  std::vector<Range> pieces{range};
  for (size_t i = 0; i < pieces.size();)  // split depth-first, as TBB would, to the grain
    if (pieces[i].is_divisible())
      pieces.push_back(Range(pieces[i], tbb::split()));
    else
      ++i;
  const size_t threads = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t i; (i = next.fetch_add(1)) < pieces.size();) body(pieces[i]);
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < std::max<size_t>(threads, 1) && t < pieces.size(); ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
}
#endif

template <class Range, class Body>
void parallelFor(const Range& range, const Body& body) {
#ifdef MRR_TSAN
  parallelForOnThreads(range, body);
#else
  tbb::parallel_for(range, body);
#endif
}

template <class Index, class Body>
void parallelFor(Index first, Index last, const Body& body) {
#ifdef MRR_TSAN
  if (first >= last) return;
  parallelForOnThreads(tbb::blocked_range<Index>(first, last), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) body(i);
  });
#else
  tbb::parallel_for(first, last, body);
#endif
}

}  // namespace mrr
