#pragma once
// The pages of `mrr compare --report` and `mrr bench --report`, and the bench's charts, are made
// by one Python program with matplotlib and Jinja2 (compare/report/report.py and its templates).
// They are compiled into mrr as text (compare/report/embed.cmake), so the binary works from
// anywhere: each report writes them into a scratch folder and runs them with /usr/bin/python3,
// not `python3` from PATH (a pyenv or virtualenv python there does not see Debian's packages).
// MRR_PYTHON=PATH names another interpreter (the tests point it at a missing one).
#include <string>

#include <nlohmann/json.hpp>

namespace mrr {

// The interpreter the reports run: $MRR_PYTHON when set, else /usr/bin/python3.
std::string reportPython();

// Throws MrrError "--report needs matplotlib and Jinja2 (…)" when the interpreter cannot import
// both. Called before any rendering, so that a missing package costs nothing and writes nothing.
void requireReportPython();

// A scratch folder holding report.py and its templates, removed with the object. C++ writes
// what the page shows into it (images as PNG files, named in the data), then runs the program.
class ReportJob {
 public:
  ReportJob();
  ~ReportJob();
  ReportJob(const ReportJob&) = delete;
  ReportJob& operator=(const ReportJob&) = delete;

  const std::string& folder() const { return folder_; }

  // Runs report.py on `data` (its "kind" is "compare" or "bench") and returns the page it made.
  // The caller writes the page into place, so a failure leaves no half-written index.html.
  // Throws MrrError naming the last line Python wrote to stderr when it fails.
  std::string makePage(const nlohmann::json& data) const;

 private:
  std::string folder_;
};

}  // namespace mrr
