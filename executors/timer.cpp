#include "executors/timer.hpp"

#include <string>

#include "core/check.hpp"
#include "executors/subscriber_queue.hpp"

namespace scancrew {

namespace {

// "100ms", "1s", "250us", "7ns": the largest unit that divides the period exactly.
std::string format_period(int64_t period_ns) {
  if (period_ns % 1'000'000'000 == 0) return std::to_string(period_ns / 1'000'000'000) + "s";
  if (period_ns % 1'000'000 == 0) return std::to_string(period_ns / 1'000'000) + "ms";
  if (period_ns % 1'000 == 0) return std::to_string(period_ns / 1'000) + "us";
  return std::to_string(period_ns) + "ns";
}

}  // namespace

Timer::Timer(Clock& clock, int64_t period_ns, Callback callback, CallbackGroup& group,
             const std::atomic<bool>* active)
    : Executable(group, active),
      clock_(clock),
      period_ns_(period_ns),
      callback_(std::move(callback)) {
  SCANCREW_CHECK(period_ns > 0, "timer period must be positive");
  next_ns_.store(now_ns() + period_ns_);
  set_trace_what("timer " + format_period(period_ns));
}

Timer::~Timer() {
  set_wake_target(nullptr);
}

int64_t Timer::now_ns() const {
  return clock_.type() == ClockType::kSim ? clock_.now_ns() : monotonic_now_ns();
}

void Timer::reset() {
  next_ns_.store(now_ns() + period_ns_, std::memory_order_release);
}

bool Timer::has_work() const {
  return now_ns() >= next_ns_.load(std::memory_order_acquire);
}

bool Timer::execute() {
  int64_t due = next_ns_.load(std::memory_order_acquire);
  const int64_t now = now_ns();
  if (now < due) return false;
  // skip the periods already missed: the next deadline is the first one after now
  const int64_t next = due + period_ns_ * (1 + (now - due) / period_ns_);
  if (!next_ns_.compare_exchange_strong(due, next, std::memory_order_acq_rel)) return false;
  fires_.fetch_add(1, std::memory_order_relaxed);
  callback_();
  return true;
}

void Timer::set_wake_target(WakeTarget* target) {
  if (clock_.type() != ClockType::kSim) return;
  // a sim timer becomes due when the sim clock advances: ask the clock to wake us
  auto& sim = static_cast<SimClock&>(clock_);
  if (listener_id_ >= 0) {
    sim.remove_listener(listener_id_);
    listener_id_ = -1;
  }
  if (target != nullptr) listener_id_ = sim.add_listener([target] { target->wake(); });
}

int64_t Timer::wall_deadline_ns() const {
  return clock_.type() == ClockType::kWall ? next_ns_.load(std::memory_order_acquire) : kNoDeadline;
}

int64_t Timer::sim_deadline_ns() const {
  return clock_.type() == ClockType::kSim ? next_ns_.load(std::memory_order_acquire) : kNoDeadline;
}

}  // namespace scancrew
