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
  std::vector<int> samples = {16, 64, 256};
  int repeats = 3;           // median of this many timed runs, after one warm-up
  int scalingSamples = 64;   // the sample count at which 1-thread vs N-thread is measured
  int threads = 0;           // N (0 = all cores)
  std::string jsonOut;       // optional: all figures as JSON
  std::string markdownOut;   // optional: the tables as Markdown
};

// Runs the sweep; prints the tables to `out` (Markdown) and returns the process exit code.
int runBench(const BenchOptions& options, std::ostream& out);

}  // namespace mrr
