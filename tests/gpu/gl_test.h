#pragma once
// Shared by the GL tests: they skip, saying why, when no GL 3.3 context can be made, unless
// MRR_REQUIRE_GL is set (CI), where that is a failure: the port's tests never pass silently.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "gpu/context.h"

#define MRR_REQUIRE_GL_OR_SKIP()                                                        \
  do {                                                                                  \
    std::string why_;                                                                   \
    if (!mrr::gpu::glAvailable(&why_)) {                                                \
      if (std::getenv("MRR_REQUIRE_GL")) FAIL() << "MRR_REQUIRE_GL is set but " << why_; \
      GTEST_SKIP() << why_;                                                             \
    }                                                                                   \
  } while (0)
