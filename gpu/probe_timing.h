#pragma once
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
namespace mrr::gpu {
struct ProbeClock {
  const char* what; std::chrono::steady_clock::time_point t0; bool on;
  explicit ProbeClock(const char* w) : what(w), on(std::getenv("MRR_PROBE_TIMING")) { if (on) { glFinish(); t0 = std::chrono::steady_clock::now(); } }
  ~ProbeClock() { if (on) { glFinish(); std::fprintf(stderr, "[probe] %s %.2f ms\n", what, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count()); } }
};
}
