#pragma once
// The `mrr` binary run as a user runs it, for the CLI tests that drive it through a shell
// (byo_test, check_test): its exit status and what it printed, and whether the port can run
// here at all. (cli_test.cpp has its own runner with timeouts and environments.)
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace mrr::cli {

struct Ran {
  int status = -1;
  std::string out, err;
};

inline std::string quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// `mrr ARGS` with stdout and stderr kept in DIR; `env` ("A=1 B=2") before it; `cd` runs it in DIR,
// so that relative paths in ARGS are DIR's.
inline Ran mrr(const std::vector<std::string>& args, const std::string& dir, const std::string& env = "",
               bool cd = false) {
  const std::string out = (std::filesystem::path(dir) / "run.stdout").string();
  const std::string err = (std::filesystem::path(dir) / "run.stderr").string();
  std::string cmd = cd ? "cd " + quote(dir) + " && " : "";
  cmd += env.empty() ? "" : env + " ";
  cmd += quote(MRR_BINARY);
  for (const std::string& a : args) cmd += " " + quote(a);
  cmd += " >" + quote(out) + " 2>" + quote(err);
  const int raw = std::system(cmd.c_str());
  Ran r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = test::readFile(out);
  r.err = test::readFile(err);
  return r;
}

// The last line of a command's output, without its trailing newlines.
inline std::string lastLine(const std::string& text) {
  std::string t = text;
  while (!t.empty() && t.back() == '\n') t.pop_back();
  return t.substr(t.rfind('\n') == std::string::npos ? 0 : t.rfind('\n') + 1);
}

// `head` followed by `tail`: a command's arguments with more appended.
inline std::vector<std::string> with(std::vector<std::string> head, const std::vector<std::string>& tail) {
  head.insert(head.end(), tail.begin(), tail.end());
  return head;
}

// Whether the port renders here (an 8×8 frame on it), asked once per test binary.
inline bool glAvailable(const std::string& dir) {
  static const bool available =
      mrr({"render", "--scene", "builtin:plane", "--path", "gpu", "--size", "8x8", "--samples", "1", "-q", "--out",
           (std::filesystem::path(dir) / "gl-probe.exr").string()},
          dir)
          .status == 0;
  return available;
}

}  // namespace mrr::cli

// Skips a test that needs the port where no EGL device gives GL 3.3 core, unless
// MRR_REQUIRE_GL=1 (CI), where that fails it.
#define REQUIRE_GL(dir)                                                              \
  if (!::mrr::cli::glAvailable(dir)) {                                               \
    const char* r = std::getenv("MRR_REQUIRE_GL");                                   \
    if (r && std::string(r) == "1") FAIL() << "no EGL device, and MRR_REQUIRE_GL=1"; \
    GTEST_SKIP() << "no EGL device with GL 3.3 core here: the port cannot run";      \
  }
