#include "gpu/traffic.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>

#include "common/error.h"

namespace mrr::gpu {

namespace {
// One GL context per thread at most, and the port's calls come from the thread that holds it:
// the counters are per thread, so frames rendered on two threads (tests) count apart.
thread_local GlTraffic counted;
}  // namespace

void readImage(int width, int height, unsigned format, unsigned type, void* data, size_t bytes) {
  glReadPixels(0, 0, width, height, format, type, data);
  ++counted.readbacks;
  counted.readbackBytes += static_cast<int64_t>(bytes);
  ++counted.waits;  // the read waits for the image's pass
}

void readCounts(int width, int height, unsigned format, unsigned type, void* data, size_t bytes) {
  require(bytes <= kSmallReadBytes, "gpu: a small read of " + std::to_string(bytes) + " bytes (at most " +
                                        std::to_string(kSmallReadBytes) + ")");
  glReadPixels(0, 0, width, height, format, type, data);
  ++counted.countReads;
  counted.readbackBytes += static_cast<int64_t>(bytes);
  ++counted.waits;
}

void finish(WaitFor why) {
  glFinish();
  ++counted.finishes;
  ++(why == WaitFor::Timing ? counted.timingWaits : counted.waits);
}

uint64_t queryResult(unsigned query, WaitFor why) {
  GLuint64 value = 0;
  glGetQueryObjectui64v(query, GL_QUERY_RESULT, &value);
  ++(why == WaitFor::Timing ? counted.timingWaits : counted.waits);
  return value;
}

GlTraffic processTraffic() { return counted; }

GlTraffic operator-(const GlTraffic& b, const GlTraffic& a) {
  GlTraffic d;
  d.readbacks = b.readbacks - a.readbacks;
  d.readbackBytes = b.readbackBytes - a.readbackBytes;
  d.countReads = b.countReads - a.countReads;
  d.waits = b.waits - a.waits;
  d.timingWaits = b.timingWaits - a.timingWaits;
  d.finishes = b.finishes - a.finishes;
  d.measured = true;
  return d;
}

}  // namespace mrr::gpu
