#pragma once
// `mrr bench`: the oracle's speed/accuracy benchmark. For each scene × size × sample count it
// renders `full` and `multires` side by side in one run, repeats each, and reports medians
// per stage, the measured speedup beside the ideal one (shaded-pixel ratio), primary rays
// per second, the error against full, and 1→N thread scaling. Progress goes to stderr.
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace mrr {

struct BenchOptions {
  std::vector<std::string> scenes = {"arcade", "apartment"};
  std::vector<std::pair<int, int>> sizes = {{1280, 720}, {1920, 1080}};
  std::vector<std::string> effects = {"ssao"};
  std::vector<int> samples;  // empty: per effect, ssao 16/64/256, ssm 100/196/324, ssgi 24/80/288
  int repeats = 3;           // median of this many timed runs, after one warm-up
  bool scaling = true;       // also measure 1 thread against N, at each effect's middle sample count
  int threads = 0;           // N (0 = all cores)
  std::string jsonOut;       // optional: all figures as JSON
  std::string markdownOut;   // optional: the tables as Markdown
};

// Runs the sweep; prints the tables to `out` (Markdown) and returns the process exit code.
int runBench(const BenchOptions& options, std::ostream& out);

}  // namespace mrr
