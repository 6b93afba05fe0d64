#pragma once

// Executable: one unit an executor can run (a subscription or a timer).
// Thread safety: has_work(), execute() and deadline queries may be called from several
// executor threads at once; execute() must tolerate losing a race (return false when the
// work it saw was taken by another thread).
// Tracing (executors/trace.hpp): an executable carries the names a Tracer reports it by
// (its component, and its topic or timer period), set at creation, and the id the last
// Tracer that attached it gave it.

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>

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

  // Trace names (set-up only; they allocate): the component ("r1/tsdf_mapper"; empty: the
  // callback group's name stands for it) and what runs (a topic name, "timer 100ms").
  void set_trace_component(std::string component) { trace_component_ = std::move(component); }
  const std::string& trace_component() const { return trace_component_; }
  const std::string& trace_what() const { return trace_what_; }
  // The id a Tracer gave this executable in Tracer::attach() (set-up only).
  static constexpr uint32_t kNoTraceId = std::numeric_limits<uint32_t>::max();
  uint32_t trace_id() const { return trace_id_; }
  void set_trace_id(uint32_t id) { trace_id_ = id; }

 protected:
  void set_trace_what(std::string what) { trace_what_ = std::move(what); }

 private:
  CallbackGroup* group_;
  const std::atomic<bool>* active_;
  std::string trace_component_;
  std::string trace_what_;
  uint32_t trace_id_ = kNoTraceId;
};

}  // namespace scancrew
