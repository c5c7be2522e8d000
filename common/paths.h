#pragma once
#include <string>

namespace mrr {
// The folder with the third-party glTF scenes: $MRR_SCENES_DIR if set, else the CMake option
// MRR_SCENES_DIR (default ../shared/scenes beside the checkout).
std::string sharedScenesDir();
// The paper's plotted figures (a CSV in the shared design folder, never copied into the repo):
// $MRR_PAPER_FIGURES if set, else <shared scenes>/../design/paper-figures.csv.
std::string paperFiguresPath();
}  // namespace mrr
