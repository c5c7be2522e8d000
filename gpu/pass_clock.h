#pragma once
// --gpu-timing passes (docs/port.md, "Where a frame's time goes, pass by pass"): a diagnostic that
// times every draw of the port alone. glFinish before and after each draw, the wall clock between,
// summed per timed stage and GL program into the frame's passTimings (the report's `passes`).
// The waits serialise the frame, so its stage times run higher than wall's or query's: read the
// passes as shares of their stage, not as the frame's cost. Every wait is counted as the clock's
// (gpu/traffic.h WaitFor::Timing), so the frame's `gl` figures stay what the frame itself needs.
#include <string>
#include <vector>

#include "common/frame.h"

namespace mrr::gpu {

class PassClock {
 public:
  // Starts timing this thread's draws; a clock already running is set aside until this one ends.
  PassClock();
  ~PassClock();
  PassClock(const PassClock&) = delete;
  PassClock& operator=(const PassClock&) = delete;
  // The timed stage the next draws belong to ("" between stages).
  void setStage(const std::string& stage) { stage_ = stage; }
  const std::string& stage() const { return stage_; }
  // What was timed, in the order each (stage, program) first drew.
  std::vector<PassTiming> take();

  // The clock running on this thread, or null: GpuScene's draws time themselves into it.
  static PassClock* running();
  void add(unsigned program, double ms);

 private:
  std::string stage_;
  std::vector<PassTiming> passes_;
  PassClock* previous_ = nullptr;
};

// Around one draw (or one batch of mesh draws): times it when a PassClock is running, else nothing.
class TimedDraw {
 public:
  TimedDraw();
  ~TimedDraw();
  TimedDraw(const TimedDraw&) = delete;
  TimedDraw& operator=(const TimedDraw&) = delete;

 private:
  PassClock* clock_;
  unsigned program_ = 0;
  double start_ = 0.0;
};

}  // namespace mrr::gpu
