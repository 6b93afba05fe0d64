#pragma once

// Executable: one unit an executor can run (a subscription or a timer).
// Thread safety: has_work(), execute() and deadline queries may be called from several
// executor threads at once; execute() must tolerate losing a race (return false when the
// work it saw was taken by another thread).

#include <atomic>
#include <cstdint>
#include <limits>

#include "executors/callback_group.hpp"
#include "executors/clock.hpp"

namespace scancrew {

class WakeTarget;

class Executable {
 public:
  static constexpr int64_t kNoDeadline = std::numeric_limits<int64_t>::max();

  // `active` (may be null) gates the executable: while it reads false the executable
  // is skipped (its component is not active).
  Executable(CallbackGroup& group, const std::atomic<bool>* active)
      : group_(&group), active_(active) {}
  virtual ~Executable() = default;
  Executable(const Executable&) = delete;
  Executable& operator=(const Executable&) = delete;

  bool enabled() const { return active_ == nullptr || active_->load(std::memory_order_acquire); }
  CallbackGroup& group() const { return *group_; }

  // Lock-free peek: is there work now?
  virtual bool has_work() const = 0;
  // Runs one unit of work; false when there was none left.
  virtual bool execute() = 0;
  // The executor to wake when work arrives (null: none). Called at set-up.
  virtual void set_wake_target(WakeTarget* target) = 0;
  // Next deadline on the monotonic clock (wall timers) or the sim clock (sim timers).
  virtual int64_t wall_deadline_ns() const { return kNoDeadline; }
  virtual int64_t sim_deadline_ns() const { return kNoDeadline; }

 private:
  CallbackGroup* group_;
  const std::atomic<bool>* active_;
};

}  // namespace scancrew
