#include "common/memory.h"

#include "common/frame_params.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "common/error.h"

namespace mrr {

namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

int64_t fromGiB(double gib, const std::string& name) {
  require(std::isfinite(gib) && gib > 0.0 && gib <= 1.0e6,
          name + ": must be a positive number of GiB (for example 8 or 0.5)");
  return static_cast<int64_t>(gib * kGiB);
}

}  // namespace

MemoryLimit memoryLimit(std::optional<double> optionGiB) {
  if (optionGiB) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", *optionGiB);
    return {fromGiB(*optionGiB, optionName(Param::MemoryLimit) + " " + text), optionName(Param::MemoryLimit)};
  }
  if (const char* env = std::getenv("MRR_MEMORY_LIMIT"); env && *env) {
    char* end = nullptr;
    const double gib = std::strtod(env, &end);
    require(end && *end == '\0', std::string("MRR_MEMORY_LIMIT=") + env + ": must be a positive number of GiB");
    return {fromGiB(gib, std::string("MRR_MEMORY_LIMIT=") + env), "MRR_MEMORY_LIMIT"};
  }
  const long pages = ::sysconf(_SC_PHYS_PAGES);
  const long pageSize = ::sysconf(_SC_PAGESIZE);
  const int64_t physical = pages > 0 && pageSize > 0 ? static_cast<int64_t>(pages) * pageSize : int64_t{8} << 30;
  return {physical / 4 * 3, "3/4 of physical memory"};
}

void requireMemory(int64_t neededBytes, const MemoryLimit& limit, const std::string& what) {
  require(neededBytes <= limit.bytes,
          what + " needs about " + formatBytes(neededBytes) + ", over the memory limit of " +
              formatBytes(limit.bytes) + " (" + limit.source +
              "); render smaller, or raise the limit with --memory-limit GIB or MRR_MEMORY_LIMIT=GIB");
}

std::string formatBytes(int64_t bytes) {
  char text[64];
  const double b = static_cast<double>(bytes);
  if (b >= kGiB)
    std::snprintf(text, sizeof text, "%.2f GiB", b / kGiB);
  else
    std::snprintf(text, sizeof text, "%.0f MiB", std::ceil(b / (1024.0 * 1024.0)));
  return text;
}

int64_t peakResidentBytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<int64_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

}  // namespace mrr
