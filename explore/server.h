#pragma once
// `mrr explore`: a local web page on one frame. Every stage as a layer, oracle and
// port side by side with their difference; click a pixel for its probe on both paths; turn
// the knobs and the frame re-renders; a step-through of the stages with docs/method.md's text.
// The page is built on a JSON API (docs/explore.md):
//   GET /api/info                       scenes, the port's status, defaults, stages, teach text
//   GET /api/frame?<frame>&path=cpu|gpu the report JSON (as `render --report`), plus "explore"
//   GET /api/stage/<layer>.png|.json    a layer's picture, or its legend
//   GET /api/value?layer=&x=&y=&path=   the layer's values under a pixel
//   GET /api/probe?x=&y=&path=cpu|gpu|both   what `mrr probe --json` prints
//   GET /api/progress                   what the renderer is doing now
// Frame parameters are the command line's option names with '_' for '-' (tau_n, size, ...).
// Renders run one at a time on one thread, which owns the GL context; the frames are cached.
#include <string>

#include "explore/budget.h"
#include "frontend/frame_options.h"

namespace mrr::explore {

struct ServerOptions {
  FrameOptions frame;  // the command line's frame: the page starts from it
  std::string host = "127.0.0.1";
  int port = 8080;  // 0: any free port
  // --budget: the most work one request may ask for, in millions of sample-pixels (one SSAO
  // sample at one pixel; explore/budget.h). Over it, a request is a 400 naming the budget.
  double budget = kDefaultBudgetM;
};

// Serves until the process is stopped. Throws MrrError (exit 2) when the options are bad or
// the port cannot be had.
int serve(const ServerOptions& options);

}  // namespace mrr::explore
