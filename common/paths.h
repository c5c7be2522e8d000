#pragma once
#include <string>

namespace mrr {
// The folder with the third-party glTF scenes: $MRR_SCENES_DIR if set, else the CMake option
// MRR_SCENES_DIR (default ../shared/scenes beside the checkout).
std::string sharedScenesDir();
}  // namespace mrr
