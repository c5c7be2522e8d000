// `mrr bench --quick`: the port beside the oracle where EGL gives GL 3.3 core, one line
// on stderr saying which paths ran; --paths still chooses, and then nothing is said.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <set>
#include <string>

#include "tests/cli/run_mrr.h"

namespace mrr::cli {
namespace {

// The smallest --quick run: one scene, one camera, one repeat, no sweeps, paths or stress scenes.
Ran quickBench(const std::string& dir, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args = {"bench", "--quick", "--scenes", "builtin:plane", "--no-sweeps", "--no-stress",
                                   "--frames", "0", "--cameras", "1", "--repeats", "1", "--effects", "ssao",
                                   "--json", dir + "/bench.json"};
  args.insert(args.end(), extra.begin(), extra.end());
  return mrr(args, dir);
}

std::set<std::string> pathsRun(const std::string& dir) {
  std::set<std::string> paths;
  const nlohmann::json figures = nlohmann::json::parse(test::readFile(dir + "/bench.json"));
  for (const auto& run : figures.at("runs")) paths.insert(run.at("path").get<std::string>());
  return paths;
}

TEST(BenchQuick, RunsThePortWhereItCanAndSaysWhichPathsRan) {
  const std::string dir = test::scratchDir();
  const Ran r = quickBench(dir);
  ASSERT_EQ(r.status, 0) << r.err;
  if (glAvailable(dir)) {
    EXPECT_NE(r.err.find("[bench] --quick: both paths, the oracle (cpu) and the port (gpu)"), std::string::npos) << r.err;
    EXPECT_EQ(pathsRun(dir), (std::set<std::string>{"cpu", "gpu"}));
  } else {
    EXPECT_NE(r.err.find("[bench] --quick: the oracle (cpu) only: the port needs EGL with GL 3.3 core; here: "),
              std::string::npos)
        << r.err;
    EXPECT_EQ(pathsRun(dir), (std::set<std::string>{"cpu"}));
  }
}

TEST(BenchQuick, PathsGivenExplicitlyWinAndNothingIsSaid) {
  const std::string dir = test::scratchDir();
  const Ran r = quickBench(dir, {"--paths", "cpu"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("[bench] --quick:"), std::string::npos) << r.err;
  EXPECT_EQ(pathsRun(dir), (std::set<std::string>{"cpu"}));
}

}  // namespace
}  // namespace mrr::cli
