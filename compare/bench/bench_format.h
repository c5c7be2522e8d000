#pragma once
// The bench's number and size formats, one definition for its tables (compare/bench/bench.cpp,
// bench_report.cpp, bench_fovea.cpp).
#include <cstdio>
#include <string>

namespace mrr::bench_format {

inline std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

inline std::string sci(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

inline std::string sizeName(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace mrr::bench_format
