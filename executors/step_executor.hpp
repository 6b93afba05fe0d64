#pragma once

// StepExecutor: deterministic execution on sim time, for lockstep simulation and tests.
//
// run_until(t) runs, on the caller's thread, everything that becomes ready up to sim
// time t: it drains ready work in registration order, then advances the sim clock to the
// earliest timer deadline <= t, fires it, drains again, and so on; the clock ends at t.
// Same inputs, same order of callbacks, whatever the speed of the machine.
//
// Compute time (set_compute_time). kFree, the default: a callback takes no sim time, as
// described above. kCharged: each executable belongs to a place (add_place: one computer,
// a robot or the ground station) or to the world (kWorld: the simulator and the mission's
// own instruments, which cost nothing). A place runs one callback at a time; a callback
// that starts at sim time t and uses c of CPU (ComputeClock: its thread, plus the TBB
// workers, spread over the place's cores, times the scale) keeps its place busy until
// t + c, and what it publishes is delivered at t + c (PublishDeferral). Work for a busy
// place waits; when the place is free again its ready executables take turns (round
// robin), so a busy input stream cannot starve a timer. Places compute in parallel in sim
// time. Charged runs are not reproducible bit for bit: CPU times vary from run to run.
//
// Thread safety: one thread drives it; publishers in other threads are allowed (their
// samples are picked up by the next drain) but make runs nondeterministic.

#include <cstdint>
#include <string>
#include <vector>

#include "executors/clock.hpp"
#include "executors/executable.hpp"
#include "executors/subscriber_queue.hpp"
#include "executors/topic.hpp"
#include "executors/trace.hpp"

namespace scancrew {

enum class ComputeTime { kFree, kCharged };
// run.compute_time: charged | free
inline constexpr EnumNames<ComputeTime, 2> kComputeTimeNames = {
    {{ComputeTime::kCharged, "charged"}, {ComputeTime::kFree, "free"}}};
std::string_view to_string(ComputeTime mode);

// The computers a charged run models: each place has `cores` cores and is `scale` times
// slower than this machine (0.5: twice as fast).
struct ComputeCharge {
  double scale = 1.0;
  int cores = 2;
};

// What a place computed in a charged run.
struct PlaceStats {
  std::string name;
  uint64_t callbacks = 0;
  double charged_s = 0;        // sim time its callbacks kept it busy
  double max_callback_ms = 0;  // the longest one
};

class StepExecutor final : public WakeTarget, private PublishDeferral {
 public:
  static constexpr int kWorld = -1;

  explicit StepExecutor(SimClock& clock) : clock_(clock) {}
  ~StepExecutor() override;
  StepExecutor(const StepExecutor&) = delete;
  StepExecutor& operator=(const StepExecutor&) = delete;

  // Set-up, before any run: how callbacks are timed.
  void set_compute_time(ComputeTime mode, ComputeCharge charge = {});
  ComputeTime compute_time() const { return mode_; }
  // A computer (set-up only); returns its index for add(). Names need not be unique.
  int add_place(std::string name);

  // Wall-clock timers are a contract violation here: they would break determinism.
  void add(Executable& executable, int place = kWorld);
  void remove(Executable& executable);

  // Returns the number of callbacks run. max_units bounds a livelock (a callback that
  // republishes to itself forever): hitting it is a contract violation.
  size_t run_until(int64_t t_ns, size_t max_units = 100'000'000);
  // Drains ready work without moving time.
  size_t drain(size_t max_units = 100'000'000);
  // Drops the outputs of charged callbacks not delivered yet (at the end of a run).
  void discard_pending();

  // Records every callback in tracer (null: none, the default); attaches the executables
  // added so far and later. Set-up only; the tracer outlives the runs.
  void set_tracer(Tracer* tracer);

  SimClock& clock() { return clock_; }
  std::vector<PlaceStats> place_stats() const;
  void wake() override {}  // nothing sleeps: run_until() looks at every executable

 private:
  struct Place {
    std::string name;
    int64_t busy_until_ns = 0;
    std::vector<Executable*> members;
    size_t next = 0;  // round robin: where the next scan of members starts
    uint64_t callbacks = 0;
    int64_t charged_ns = 0, max_ns = 0;
  };
  struct Delivery {
    int64_t due_ns;
    uint64_t order;
    TopicBase* topic;
    uint32_t index;
  };

  void defer(TopicBase& topic, uint32_t index) override;
  bool execute(Executable& e);
  bool execute_charged(Executable& e, Place& place);
  size_t drain_charged(size_t max_units);
  void deliver_due();
  int64_t next_event_ns() const;
  bool busy(const Place& place) const { return place.busy_until_ns > clock_.now_ns(); }

  SimClock& clock_;
  std::vector<Executable*> executables_;
  std::vector<int> place_of_;  // per executable: its place, or kWorld
  Tracer* tracer_ = nullptr;
  ComputeTime mode_ = ComputeTime::kFree;
  ComputeCharge charge_;
  std::vector<Place> places_;
  std::vector<Delivery> pending_;                          // a min-heap on (due_ns, order)
  std::vector<std::pair<TopicBase*, uint32_t>> deferred_;  // the running callback's
  uint64_t delivery_order_ = 0;
};

}  // namespace scancrew
