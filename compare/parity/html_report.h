#pragma once
// `mrr compare --report DIR`: a self-contained HTML page (DIR/index.html, every image
// embedded as a data: URI, no script or style fetched from anywhere) that shows, for every
// stage of every compared frame, the oracle's and the port's images side by side with a
// heat map of |Δ| and the figures of compare/parity/parity.h; the worst pixels of each failing or
// inherited stage with the `mrr probe --path both` command that explains them; and the
// scene's credit line. C++ prepares the images (display images, heat maps, shrinking) and the
// figures; compare/report/templates/compare.html.j2 lays out the page (compare/report/report_python.h).
#include <string>
#include <vector>

#include "compare/parity/parity.h"
#include "common/frame.h"

namespace mrr {

struct ComparedFrame {
  std::string effect;       // "ssao", "ssm", "ssgi"
  const FrameResult* oracle = nullptr;
  const FrameResult* port = nullptr;
  ParityResult result;
  std::string probeCommand;  // the `mrr probe …` command line for this frame, without --pixel
};

struct CompareReportInfo {
  std::string scene;
  std::string credit;
  std::string renderer;  // GL_RENDERER of the port
  std::string command;   // the `mrr compare …` command that made the report
  std::string subject = "the GL port";  // what the oracle is compared with (compare --against: the file)
};

// Writes DIR/index.html atomically (DIR must exist and be writable). Needs requireReportPython().
void writeCompareReport(const std::string& dir, const CompareReportInfo& info, const std::vector<ComparedFrame>& frames);

}  // namespace mrr
