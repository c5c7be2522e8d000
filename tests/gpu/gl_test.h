#pragma once
// Shared by the GL tests: they skip, saying why, when no GL 3.3 context can be made, unless
// MRR_REQUIRE_GL is set (CI), where that is a failure: the port's tests never pass silently.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "common/image.h"
#include "gpu/context.h"

#define MRR_REQUIRE_GL_OR_SKIP()                                                        \
  do {                                                                                  \
    std::string why_;                                                                   \
    if (!mrr::gpu::glAvailable(&why_)) {                                                \
      if (std::getenv("MRR_REQUIRE_GL")) FAIL() << "MRR_REQUIRE_GL is set but " << why_; \
      GTEST_SKIP() << why_;                                                             \
    }                                                                                   \
  } while (0)

namespace mrr::test {
// Two float images of one size with the same bits (no tolerance).
inline bool sameBits(const ImageF& a, const ImageF& b) {
  return a.width == b.width && a.height == b.height && a.data.size() == b.data.size() &&
         std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}
}  // namespace mrr::test
