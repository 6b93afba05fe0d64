#pragma once

// Timer: calls its callback every period on its clock. On a wall clock the deadlines are
// on the monotonic clock; on a sim clock they are sim times, so a timer fires exactly at
// t0 + k·period of simulated time, however fast the simulation runs.
// Missed periods are skipped, not queued (a slow callback does not cause a burst).
// Thread safety: see Executable; the deadline is claimed with a compare-exchange, so two
// threads never fire the same deadline. Allocation: none after construction.

#include <atomic>
#include <cstdint>
#include <functional>

#include "executors/executable.hpp"

namespace scancrew {

class Timer final : public Executable {
 public:
  using Callback = std::function<void()>;

  Timer(Clock& clock, int64_t period_ns, Callback callback, CallbackGroup& group,
        const std::atomic<bool>* active);
  ~Timer() override;

  // Restarts the period from now (the first firing is one period later).
  void reset();

  bool has_work() const override;
  bool execute() override;
  void set_wake_target(WakeTarget* target) override;
  int64_t wall_deadline_ns() const override;
  int64_t sim_deadline_ns() const override;

  int64_t period_ns() const { return period_ns_; }
  uint64_t fire_count() const { return fires_.load(std::memory_order_relaxed); }

 private:
  int64_t now_ns() const;

  Clock& clock_;
  int64_t period_ns_;
  Callback callback_;
  std::atomic<int64_t> next_ns_;
  std::atomic<uint64_t> fires_{0};
  int listener_id_ = -1;
};

}  // namespace scancrew
