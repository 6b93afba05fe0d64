#pragma once

// Clocks. Every component reads time through the Clock its context gives it, so the
// same graph runs on wall time (hardware) or on sim time (the team simulator advances
// it; lockstep runs are deterministic).
//
// Thread safety: now_ns() may be called from any thread. SimClock::advance_to() is
// called by the one thread that owns simulated time (the simulator or a StepExecutor).

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string_view>
#include <vector>

#include "core/enum_names.hpp"

namespace scancrew {

enum class ClockType { kWall, kSim };
inline constexpr EnumNames<ClockType, 2> kClockTypeNames = {
    {{ClockType::kWall, "wall"}, {ClockType::kSim, "sim"}}};
std::string_view to_string(ClockType type);

// Monotonic time of this machine in ns, used for publish times and latency tracing.
inline int64_t monotonic_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

class Clock {
 public:
  virtual ~Clock() = default;
  // Current time in ns: since the Unix epoch for the wall clock, since the start of the
  // simulation for the sim clock.
  virtual int64_t now_ns() const = 0;
  virtual ClockType type() const = 0;
};

// Wall time. Timers on a wall clock wait on the monotonic clock (immune to time jumps).
class WallClock final : public Clock {
 public:
  int64_t now_ns() const override;
  ClockType type() const override { return ClockType::kWall; }
};

// Simulated time: starts at 0 and moves only when its owner advances it. Listeners
// (executors with sim-time timers) are told after every advance.
class SimClock final : public Clock {
 public:
  using Listener = std::function<void()>;

  int64_t now_ns() const override { return now_ns_.load(std::memory_order_acquire); }
  ClockType type() const override { return ClockType::kSim; }

  // Moves time forward to t_ns (never backward: a smaller t is a contract violation).
  void advance_to(int64_t t_ns);

  // Registers a callback run after each advance (on the advancing thread). Returns an id
  // for remove_listener(). Allocates; call at set-up, not on the hot path.
  int add_listener(Listener listener);
  void remove_listener(int id);

 private:
  std::atomic<int64_t> now_ns_{0};
  std::mutex listeners_mutex_;
  std::vector<std::pair<int, Listener>> listeners_;
  int next_listener_id_ = 0;
};

}  // namespace scancrew
