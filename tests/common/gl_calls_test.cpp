// The port talks back to the host only through gpu/traffic.cpp (readImage, readCounts, finish,
// queryResult), where every call is counted for the report's `gl` object (docs/port.md). This
// reads the port's sources: a GL call that reads or waits anywhere else would go uncounted, and a
// resident frame that reads nothing back could not be told from one that reads uncounted.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

// The GL calls that bring data back or wait for the GPU.
const std::regex kTalksBack(
    R"(\bgl(ReadPixels|Finish|GetQueryObject\w*|ClientWaitSync|GetTexImage|GetBufferSubData|MapBuffer\w*)\s*\()");

std::vector<std::string> callsIn(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::vector<std::string> calls;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), kTalksBack); it != std::sregex_iterator(); ++it)
    calls.push_back(it->str());
  return calls;
}

}  // namespace

TEST(GlCalls, OnlyTheCountedWrappersReadBackOrWait) {
  const std::filesystem::path gpu = std::filesystem::path(MRR_SOURCE_DIR) / "gpu";
  ASSERT_TRUE(std::filesystem::is_directory(gpu)) << gpu;
  size_t scanned = 0;
  for (const auto& entry : std::filesystem::directory_iterator(gpu)) {
    const std::string ext = entry.path().extension().string();
    if (ext != ".cpp" && ext != ".h") continue;
    ++scanned;
    const std::vector<std::string> calls = callsIn(entry.path());
    if (entry.path().filename() == "traffic.cpp") {
      // The wrappers themselves: the scan must see their calls, or it sees nothing anywhere.
      EXPECT_GE(calls.size(), 4u) << "gpu/traffic.cpp: the scan no longer finds its own calls";
      continue;
    }
    for (const std::string& call : calls)
      ADD_FAILURE() << "gpu/" << entry.path().filename().string() << " calls " << call
                    << " directly: go through gpu/traffic.h so the report counts it";
  }
  EXPECT_GT(scanned, 20u);
}
