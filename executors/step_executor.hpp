#pragma once

// StepExecutor: deterministic execution on sim time, for lockstep simulation and tests.
//
// run_until(t) runs, on the caller's thread, everything that becomes ready up to sim
// time t: it drains ready work in registration order, then advances the sim clock to the
// earliest timer deadline <= t, fires it, drains again, and so on; the clock ends at t.
// Same inputs, same order of callbacks, whatever the speed of the machine.
//
// Thread safety: one thread drives it; publishers in other threads are allowed (their
// samples are picked up by the next drain) but make runs nondeterministic.

#include <cstdint>
#include <vector>

#include "executors/clock.hpp"
#include "executors/executable.hpp"
#include "executors/subscriber_queue.hpp"
#include "executors/trace.hpp"

namespace scancrew {

class StepExecutor final : public WakeTarget {
 public:
  explicit StepExecutor(SimClock& clock) : clock_(clock) {}
  ~StepExecutor() override;
  StepExecutor(const StepExecutor&) = delete;
  StepExecutor& operator=(const StepExecutor&) = delete;

  // Wall-clock timers are a contract violation here: they would break determinism.
  void add(Executable& executable);
  void remove(Executable& executable);

  // Returns the number of callbacks run. max_units bounds a livelock (a callback that
  // republishes to itself forever): hitting it is a contract violation.
  size_t run_until(int64_t t_ns, size_t max_units = 100'000'000);
  // Drains ready work without moving time.
  size_t drain(size_t max_units = 100'000'000);

  // Records every callback in tracer (null: none, the default); attaches the executables
  // added so far and later. Set-up only; the tracer outlives the runs.
  void set_tracer(Tracer* tracer);

  SimClock& clock() { return clock_; }
  void wake() override {}  // nothing sleeps: run_until() looks at every executable

 private:
  SimClock& clock_;
  std::vector<Executable*> executables_;
  Tracer* tracer_ = nullptr;
};

}  // namespace scancrew
