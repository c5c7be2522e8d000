#include "compare/report/report_python.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/error.h"
#include "compare/report/process.h"
#include "compare/report_files.h"

namespace mrr {

namespace fs = std::filesystem;

namespace {

std::string lastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (const size_t start = line.find_first_not_of(" \t\r"); start != std::string::npos) last = line.substr(start);
  return last.empty() ? "(no message)" : last;
}

void writeScratch(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw MrrError("--report: cannot write " + path.string() + ": " + std::strerror(errno));
}

}  // namespace

std::string reportPython() {
  const char* env = std::getenv("MRR_PYTHON");
  return env && *env ? env : "/usr/bin/python3";
}

void requireReportPython() {
  std::string why;
  if (runProcess({reportPython(), "-c", "import matplotlib, jinja2"}, "/dev/null", why) != 0)
    throw MrrError("--report needs matplotlib and Jinja2 (Debian: apt-get install python3-matplotlib python3-jinja2)");
}

ReportJob::ReportJob() {
  std::string name = (fs::temp_directory_path() / "mrr-report-XXXXXX").string();
  if (!mkdtemp(name.data()))
    throw MrrError("--report: cannot make a scratch folder " + name + ": " + std::strerror(errno));
  folder_ = name;
  try {
    for (const ReportFile& f : kReportFiles) {
      const fs::path path = fs::path(folder_) / f.path;
      fs::create_directories(path.parent_path());
      writeScratch(path, f.text);
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(folder_, ignored);
    throw;
  }
}

ReportJob::~ReportJob() {
  std::error_code ignored;
  fs::remove_all(folder_, ignored);
}

std::string ReportJob::makePage(const nlohmann::json& data) const {
  const std::string input = folder_ + "/data.json", page = folder_ + "/index.html", log = folder_ + "/python.log";
  // Invalid UTF-8 (a scene's credit line) is replaced rather than refused: the page still says the rest.
  writeScratch(input, data.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  std::string why;
  const int status = runProcess({reportPython(), folder_ + "/report.py", input, page}, log, why);
  if (status != 0)
    throw MrrError("--report: " + (status < 0 ? "cannot run " + why
                                              : reportPython() + " report.py exited " + std::to_string(status) +
                                                    ": " + lastLine(log)));
  std::ifstream in(page, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in || text.str().empty()) throw MrrError("--report: " + reportPython() + " report.py wrote no page");
  return text.str();
}

}  // namespace mrr
