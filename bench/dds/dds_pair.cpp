#include "bench/dds/dds_pair.hpp"

#include <chrono>
#include <cstring>

#include "core/check.hpp"
#include "executors/clock.hpp"

namespace scancrew::bench {

void stamp_payload(std::span<uint8_t> payload, uint32_t phase, uint32_t index) {
  SCANCREW_CHECK(payload.size() >= kDdsBenchHeaderBytes, "a bench payload holds its header");
  const int64_t now = monotonic_now_ns();
  std::memcpy(payload.data(), &now, 8);
  std::memcpy(payload.data() + 8, &phase, 4);
  std::memcpy(payload.data() + 12, &index, 4);
}

void Arrivals::start_phase(uint32_t phase, size_t expected) {
  std::lock_guard lock(mutex_);
  phase_ = phase;
  delays_ns_.clear();
  delays_ns_.reserve(expected);
  last_arrival_ns_ = 0;
}

void Arrivals::arrived(std::span<const uint8_t> payload) {
  const int64_t now = monotonic_now_ns();
  std::lock_guard lock(mutex_);
  int64_t sent = 0;
  uint32_t phase = 0;
  if (payload.size() >= kDdsBenchHeaderBytes) {
    std::memcpy(&sent, payload.data(), 8);
    std::memcpy(&phase, payload.data() + 8, 4);
  }
  if (payload.size() < kDdsBenchHeaderBytes || phase != phase_) {
    ++stale_;
    return;
  }
  delays_ns_.push_back(now - sent);
  last_arrival_ns_ = now;
  arrived_.notify_all();
}

bool Arrivals::wait_for(size_t n, double timeout_s) {
  std::unique_lock lock(mutex_);
  return arrived_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                           [&] { return delays_ns_.size() >= n; });
}

size_t Arrivals::count() const {
  std::lock_guard lock(mutex_);
  return delays_ns_.size();
}

size_t Arrivals::stale() const {
  std::lock_guard lock(mutex_);
  return stale_;
}

int64_t Arrivals::last_arrival_ns() const {
  std::lock_guard lock(mutex_);
  return last_arrival_ns_;
}

std::vector<int64_t> Arrivals::delays_ns() const {
  std::lock_guard lock(mutex_);
  return delays_ns_;
}

}  // namespace scancrew::bench
