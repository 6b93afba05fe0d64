#pragma once

// SamplePool<T>: the fixed set of slots a topic hands out. Each slot holds one T that
// lives as long as the pool: a recycled slot keeps what its last user left, so
// variable-size payloads (std::vector members) keep their capacity and steady-state use
// allocates nothing.
//
// Ownership: a slot has a reference count. acquire() returns a slot with count 1;
// retain()/release() move it; the slot goes back to the free list when the count drops
// to zero. Thread safety: all member functions may be called from any thread.
// Allocation: only the constructor allocates.

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "core/check.hpp"

namespace scancrew {

template <class T>
class SamplePool {
 public:
  explicit SamplePool(size_t capacity)
      : slots_(std::make_unique<Slot[]>(capacity)), capacity_(capacity) {
    SCANCREW_CHECK(capacity > 0 && capacity < UINT32_MAX, "pool capacity out of range");
    free_.reserve(capacity);
    for (size_t i = capacity; i-- > 0;) free_.push_back(static_cast<uint32_t>(i));
  }
  SamplePool(const SamplePool&) = delete;
  SamplePool& operator=(const SamplePool&) = delete;
  ~SamplePool() {
    // A sample that outlives its topic would point into freed memory.
    SCANCREW_CHECK(free_.size() == capacity_, "a sample outlived its topic's pool");
  }

  std::optional<uint32_t> acquire() {
    std::lock_guard lock(mutex_);
    if (free_.empty()) return std::nullopt;
    const uint32_t index = free_.back();
    free_.pop_back();
    slots_[index].refs.store(1, std::memory_order_relaxed);
    return index;
  }

  void retain(uint32_t index) { slots_[index].refs.fetch_add(1, std::memory_order_relaxed); }

  void release(uint32_t index) {
    const uint32_t before = slots_[index].refs.fetch_sub(1, std::memory_order_acq_rel);
    SCANCREW_CHECK(before > 0, "slot released more often than retained");
    if (before == 1) {
      std::lock_guard lock(mutex_);
      free_.push_back(index);
    }
  }

  T& at(uint32_t index) { return slots_[index].value; }
  const T& at(uint32_t index) const { return slots_[index].value; }
  uint32_t refs(uint32_t index) const { return slots_[index].refs.load(std::memory_order_acquire); }

  size_t capacity() const { return capacity_; }
  size_t available() const {
    std::lock_guard lock(mutex_);
    return free_.size();
  }

 private:
  struct Slot {
    T value{};
    std::atomic<uint32_t> refs{0};
  };
  std::unique_ptr<Slot[]> slots_;
  size_t capacity_;
  mutable std::mutex mutex_;
  std::vector<uint32_t> free_;  // reserved to capacity_: push/pop never allocate
};

}  // namespace scancrew
