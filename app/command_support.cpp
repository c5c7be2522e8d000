// What the subcommands share: output checks, progress lines, threads, report folders.
#include <tbb/task_arena.h>

#include <cctype>
#include <filesystem>
#include <iostream>

#include "app/commands.h"
#include "common/error.h"
#include "common/image_io.h"
#include "frontend/frame_file.h"

namespace mrr {

void checkOutput(const std::string& path, const std::string& option, const std::vector<std::string>& extensions) {
  std::string lower = path;
  for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  bool ok = false;
  std::string list;
  for (const std::string& e : extensions) {
    ok = ok || (lower.size() > e.size() && lower.compare(lower.size() - e.size(), e.size(), e) == 0);
    list += (list.empty() ? "" : " or ") + e;
  }
  require(ok, option + " " + path + ": expected a " + list + " file");
  checkOutputLocation(path, option);
}

void requireDistinct(const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i)
    for (size_t j = i + 1; j < outputs.size(); ++j)
      require(outputs[i].second.empty() || outputs[i].second != outputs[j].second,
              outputs[i].first + " and " + outputs[j].first + " name the same file " + outputs[i].second);
}

ProgressFn progressPrinter(bool quiet, const std::string& what) {
  if (quiet) return {};
  return [what](const std::string& stage) { std::cerr << "[mrr] " << what << ": " << stage << "\n"; };
}

int threadCount(int requested) { return requested > 0 ? requested : tbb::this_task_arena::max_concurrency(); }

// What cannot be made is left to checkOutputLocation, which names the reason.
void makeReportDir(const std::string& dir, const std::string& option) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) std::filesystem::create_directories(dir, ec);
  checkOutputLocation((std::filesystem::path(dir) / "index.html").string(), option);
}

std::string frameCommandLine(const nlohmann::json& frame) {
  std::string line;
  for (const std::string& w : frameArgs(frame, "frame")) {
    const bool plain = w.find_first_of(" '\"$`\\*?[]{}()<>|&;!#~") == std::string::npos;
    std::string quoted = plain ? w : "'" + w + "'";
    line += (line.empty() ? "" : " ") + quoted;
  }
  return line;
}

}  // namespace mrr
