#include "gpu/pass_clock.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <chrono>

#include "gpu/program.h"
#include "gpu/traffic.h"

namespace mrr::gpu {

namespace {
thread_local PassClock* current = nullptr;

double nowMs() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

PassClock::PassClock() : previous_(current) { current = this; }
PassClock::~PassClock() { current = previous_; }
PassClock* PassClock::running() { return current; }

std::vector<PassTiming> PassClock::take() { return std::move(passes_); }

void PassClock::add(unsigned program, double ms) {
  const ProgramName name = programName(program);
  const std::string pass = name.stage.empty() ? "program " + std::to_string(program) : name.stage;
  const auto same = [&](const PassTiming& p) { return p.stage == stage_ && p.pass == pass; };
  auto it = std::find_if(passes_.begin(), passes_.end(), same);
  if (it == passes_.end()) it = passes_.insert(passes_.end(), PassTiming{stage_, pass, name.fragment, 0, 0.0});
  it->calls += 1;
  it->ms += ms;
}

TimedDraw::TimedDraw() : clock_(PassClock::running()) {
  if (!clock_) return;
  GLint program = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  program_ = static_cast<unsigned>(program);
  finish(WaitFor::Timing);  // the work queued before it is not its own
  start_ = nowMs();
}

TimedDraw::~TimedDraw() {
  if (!clock_) return;
  finish(WaitFor::Timing);
  clock_->add(program_, nowMs() - start_);
}

}  // namespace mrr::gpu
