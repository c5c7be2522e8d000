#include "common/paths.h"

#include <cstdlib>

namespace mrr {
std::string sharedScenesDir() {
  if (const char* env = std::getenv("MRR_SCENES_DIR"); env && *env) return env;
  return MRR_DEFAULT_SCENES_DIR;
}
}  // namespace mrr
