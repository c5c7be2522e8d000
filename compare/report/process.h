#pragma once
// Running a child process: the reports' Python and the bench's cold single-frame renders.
#include <string>
#include <vector>

namespace mrr {

// Runs `args` (args[0] is a path, not looked up in PATH) with stdin from /dev/null and stdout
// and stderr into `log`; returns its exit status (128 + the signal when killed), or -1 with
// `why` set when it could not be started.
int runProcess(const std::vector<std::string>& args, const std::string& log, std::string& why);

// This executable's path (/proc/self/exe), for running itself.
std::string selfExecutable();

}  // namespace mrr
