#pragma once
// Every call of the port that talks back to the host goes through here and is counted: image
// readbacks (glReadPixels), small reads of counts (the never-slower rule's and the report's few
// integers), and waits (glFinish, query results). The report's `gl` object (docs/port.md, "What
// a frame costs the host") gives what a frame did of each; a test holds the resident frame to
// none of the first and a few bytes of the second. Nothing in gpu/ calls those GL functions
// elsewhere (tests/cli/resident_test.cpp reads the sources).
#include <cstddef>
#include <cstdint>

#include "common/frame.h"

namespace mrr::gpu {

// Why the port waits: for the frame's own work (a decision that needs a count), or for the
// clock (the wall clock's glFinish per stage, the timer queries' results).
enum class WaitFor { Frame, Timing };

// The most a small read may bring back: a few integers, never an image.
inline constexpr size_t kSmallReadBytes = 1024;

// glReadPixels of an image (the bound read framebuffer's read buffer) into `data`, `bytes` long.
void readImage(int width, int height, unsigned format, unsigned type, void* data, size_t bytes);
// glReadPixels of a few integers (at most kSmallReadBytes; more is an MrrError): one wait.
void readCounts(int width, int height, unsigned format, unsigned type, void* data, size_t bytes);
// glFinish.
void finish(WaitFor why);
// glGetQueryObjectui64v(GL_QUERY_RESULT): a wait unless the result is known to be there.
uint64_t queryResult(unsigned query, WaitFor why);

// What the process has said to the host so far.
GlTraffic processTraffic();
// b − a, field by field.
GlTraffic operator-(const GlTraffic& b, const GlTraffic& a);

}  // namespace mrr::gpu
