// A whole `mrr render --path gpu` process as a user runs it (docs/port.md, "What a frame costs
// the host"): asked for a report alone, the port reads no image back at all, in the frame or after
// it, and with `--gpu-timing query` waits with glFinish once (when the frame's clock stops); the
// rule's counts come back as a few integers. Asked for the final image, that image comes back
// after the clock. The report's `gl` object says so, counted where the port calls GL. (A tiles
// report counts the tiles' rates from their map, read after the frame; a gaze's report, its rings.)
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/cli/run_mrr.h"
#include "tests/test_support.h"

namespace mrr {
namespace {

using cli::mrr;
using cli::Ran;
namespace fs = std::filesystem;

nlohmann::json render(const std::string& dir, const std::string& effect, const std::string& method,
                      const std::vector<std::string>& more) {
  const std::string report = (fs::path(dir) / (effect + "-" + method + ".json")).string();
  std::vector<std::string> args = {"render",   "--path",  "gpu",  "--scene",  "builtin:demo",
                                   "--size",   "160x90",  "--samples", effect == "ssm" ? "16" : "8",  // SSM: n×n
                                   "--effect", effect,    "--method",  method,  "--report", report, "-q"};
  args.insert(args.end(), more.begin(), more.end());
  const Ran r = mrr(args, dir);
  EXPECT_EQ(r.status, 0) << r.err;
  return r.status == 0 ? nlohmann::json::parse(test::readFile(report)) : nlohmann::json::object();
}

TEST(ResidentRender, AReportAloneReadsNoImageAndFinishesOnce) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  for (const std::string effect : {"ssao", "ssm", "ssgi"})
    for (const std::string row : {"mrr", "full", "uniform-2", "mrr-effect", "mrr-effect+notrim"}) {  // tiles' report reads its rate map
      // mrr-effect with the rule off, so that its budget (SPEC §12.4) selects on the GPU at this size;
      // by default with SPEC §12.5's trim (its passes resident too), and without it, where the
      // budget binds on every effect at this size
      const bool notrim = row == "mrr-effect+notrim";
      const std::string method = notrim ? "mrr-effect" : row;
      std::vector<std::string> more = {"--gpu-timing", "query"};
      if (method == "mrr-effect") more.insert(more.end(), {"--never-slower", "off"});
      if (notrim) more.insert(more.end(), {"--effect-trim", "off"});
      const nlohmann::json j = render(dir, effect, method, more);
      ASSERT_TRUE(j.contains("gl")) << effect << " " << method;
      const nlohmann::json& gl = j["gl"];
      const std::string what = effect + " " + method + ": " + gl.dump();
      if (notrim) {
        int64_t taken = 0;
        for (const nlohmann::json& level : j["effect_budget"]["levels"]) taken += level.value("taken", int64_t{0});
        EXPECT_GT(taken, 0) << effect << ": the budget marked nothing, the check would not hold it";
      }
      EXPECT_EQ(gl["process"]["readbacks"], 0) << what;
      EXPECT_LE(gl["process"]["readback_bytes"].get<int64_t>(), 1024) << what;
      EXPECT_LE(gl["process"]["finishes"].get<int64_t>(), 1) << what;
      EXPECT_EQ(gl["readbacks"], 0) << what;
      EXPECT_LE(gl["readback_bytes"].get<int64_t>(), 1024) << what;
      EXPECT_GT(j["shaded_pixels_total"].get<int64_t>(), 0) << what;  // counted on the GPU
    }
}

TEST(ResidentRender, TheFinalImageComesBackAfterTheFrame) {
  const std::string dir = test::scratchDir();
  REQUIRE_GL(dir);
  const nlohmann::json j = render(dir, "ssao", "mrr", {"--out", (fs::path(dir) / "final.exr").string()});
  ASSERT_TRUE(j.contains("gl"));
  EXPECT_EQ(j["gl"]["readbacks"], 0) << j["gl"].dump();
  EXPECT_GE(j["gl"]["after_frame"]["readbacks"].get<int64_t>(), 2) << j["gl"].dump();  // the final image, level map
  EXPECT_GT(j["gl"]["timing_waits"].get<int64_t>(), 0) << "llvmpipe's wall clock: a glFinish per stage";
  EXPECT_TRUE(fs::exists(fs::path(dir) / "final.exr"));
}

// The counters see every call: nothing in gpu/ reads back, finishes or waits but gpu/traffic.*.
TEST(ResidentRender, OnlyTheCountedWrappersTalkBackToTheHost) {
  static const std::regex raw(R"(\b(glReadPixels|glGetTexImage|glFinish|glGetQueryObject\w*|glClientWaitSync|glGetBufferSubData|glMapBuffer\w*)\s*\()");
  int files = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(MRR_SOURCE_DIR) / "gpu")) {
    if (entry.path().extension() != ".cpp" && entry.path().extension() != ".h") continue;
    ++files;
    if (entry.path().stem() == "traffic") continue;
    const std::string text = test::readFile(entry.path().string());
    std::smatch m;
    EXPECT_FALSE(std::regex_search(text, m, raw)) << entry.path().filename() << " calls " << m.str(1)
                                                  << " itself: use gpu/traffic.h, which counts it";
  }
  EXPECT_GT(files, 10);
}

}  // namespace
}  // namespace mrr
