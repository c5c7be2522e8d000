// A planted data race for the TSan build (scripts/test-sanitizers.sh): two pieces of one
// parallelFor write the same int without synchronisation. TSan must report it and exit
// non-zero — proof that the build sees races in mrr's loops at all (common/parallel.h runs
// them on std::threads there, since libtbb is not instrumented).
#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "common/parallel.h"

int main() {
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 4);
  static int shared = 0;
  mrr::parallelFor(0, 64, [](int i) {
    shared += i;  // the race
    std::this_thread::sleep_for(std::chrono::microseconds(200));  // so that every thread gets pieces
  });
  std::printf("sum %d\n", shared);
  return 0;
}
