#include "executors/clock.hpp"

#include <algorithm>

#include "core/check.hpp"

namespace scancrew {

std::string_view to_string(ClockType type) {
  return name_of(kClockTypeNames, type);
}

int64_t WallClock::now_ns() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void SimClock::advance_to(int64_t t_ns) {
  SCANCREW_CHECK(t_ns >= now_ns_.load(), "sim time must not go backward");
  now_ns_.store(t_ns, std::memory_order_release);
  std::lock_guard lock(listeners_mutex_);
  for (auto& [id, listener] : listeners_) listener();
}

int SimClock::add_listener(Listener listener) {
  std::lock_guard lock(listeners_mutex_);
  listeners_.emplace_back(next_listener_id_, std::move(listener));
  return next_listener_id_++;
}

void SimClock::remove_listener(int id) {
  std::lock_guard lock(listeners_mutex_);
  std::erase_if(listeners_, [id](const auto& entry) { return entry.first == id; });
}

}  // namespace scancrew
