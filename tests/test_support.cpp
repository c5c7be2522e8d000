#include "tests/test_support.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "common/paths.h"

namespace fs = std::filesystem;

namespace mrr::test {

std::string scratchDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "misc";
  for (char& c : name)
    if (c == '/') c = '_';
  fs::path dir = fs::path(MRR_TEST_TMP) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string sharedScene(const std::string& relative) {
  return (fs::path(sharedScenesDir()) / relative).string();
}

bool haveSharedScene(const std::string& relative) { return fs::exists(sharedScene(relative)); }

}  // namespace mrr::test
