#pragma once
// Built-in analytic scenes. Each models only what its test needs (brief: "model no more
// than a scene needs"), and carries its own camera. `demo` is the default scene of the
// README's first command: it shows every part of the method in one frame.
#include <string>
#include <vector>

#include "common/scene.h"

namespace mrr {

// Names accepted after "builtin:".
const std::vector<std::string>& builtinSceneNames();

// One line per scene saying what it is for (for --help and docs).
std::string builtinSceneDescription(const std::string& name);

// Throws MrrError for an unknown name.
Scene makeBuiltinScene(const std::string& name);

}  // namespace mrr
