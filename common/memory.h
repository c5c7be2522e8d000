#pragma once
// The memory check made before a render allocates anything (docs/hardening.md): the run's
// estimate against a limit, refused with both figures when over. The limit is, in order,
// --memory-limit GIB, the environment variable MRR_MEMORY_LIMIT (GiB), or 3/4 of the
// machine's physical memory.
#include <cstdint>
#include <optional>
#include <string>

namespace mrr {

struct MemoryLimit {
  int64_t bytes = 0;
  std::string source;  // "--memory-limit", "MRR_MEMORY_LIMIT" or "3/4 of physical memory"
};

// Throws MrrError for a limit that is not a positive number of GiB.
MemoryLimit memoryLimit(std::optional<double> optionGiB);

// Throws MrrError, one line with the estimate, the limit and how to raise it, when
// `neededBytes` is over the limit. `what` names the work ("a 16384x16384 ssao frame").
void requireMemory(int64_t neededBytes, const MemoryLimit& limit, const std::string& what);

// "1.25 GiB", "310 MiB": for messages and reports.
std::string formatBytes(int64_t bytes);

// This process's peak resident set so far (getrusage), in bytes.
int64_t peakResidentBytes();

}  // namespace mrr
