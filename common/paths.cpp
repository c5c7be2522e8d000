#include "common/paths.h"

#include <cstdlib>

namespace mrr {
std::string sharedScenesDir() {
  if (const char* env = std::getenv("MRR_SCENES_DIR"); env && *env) return env;
  return MRR_DEFAULT_SCENES_DIR;
}
std::string paperFiguresPath() {
  if (const char* env = std::getenv("MRR_PAPER_FIGURES"); env && *env) return env;
  return sharedScenesDir() + "/../design/paper-figures.csv";
}
}  // namespace mrr
