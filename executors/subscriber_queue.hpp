#pragma once

// SubscriberQueue: one subscription's bounded FIFO of slot indices, plus its counters.
// The owning topic guards push/pop with its mutex; size() is a lock-free peek the
// executors use to see which subscriptions have work.

#include <atomic>
#include <cstdint>
#include <vector>

#include "executors/latency_histogram.hpp"
#include "executors/qos.hpp"

namespace scancrew {

// Something to wake when a queue receives a sample (an executor). wake() must be
// thread safe, cheap and allocation-free.
class WakeTarget {
 public:
  virtual ~WakeTarget() = default;
  virtual void wake() = 0;
};

class SubscriberQueue {
 public:
  explicit SubscriberQueue(SubscriptionQos qos) : qos_(qos), ring_(qos.depth) {}

  const SubscriptionQos& qos() const { return qos_; }
  size_t size() const { return size_.load(std::memory_order_acquire); }

  // --- called with the topic mutex held ---
  bool full() const { return count_ == ring_.size(); }
  void push(uint32_t index) {
    ring_[(head_ + count_) % ring_.size()] = index;
    ++count_;
    size_.store(count_, std::memory_order_release);
  }
  uint32_t pop() {
    const uint32_t index = ring_[head_];
    head_ = (head_ + 1) % ring_.size();
    --count_;
    size_.store(count_, std::memory_order_release);
    return index;
  }
  bool empty() const { return count_ == 0; }

  void set_wake_target(WakeTarget* target) {
    wake_target_.store(target, std::memory_order_release);
  }
  void wake() {
    if (WakeTarget* target = wake_target_.load(std::memory_order_acquire)) target->wake();
  }

  // counters: any thread
  std::atomic<uint64_t> received{0};  // samples pushed into the queue
  std::atomic<uint64_t> dropped{0};   // samples evicted unread (keep-last overflow)
  std::atomic<uint64_t> taken{0};     // samples handed to the callback
  LatencyHistogram latency;           // publish -> callback start, ns

 private:
  SubscriptionQos qos_;
  std::vector<uint32_t> ring_;
  size_t head_ = 0;
  size_t count_ = 0;
  std::atomic<size_t> size_{0};
  std::atomic<WakeTarget*> wake_target_{nullptr};
};

}  // namespace scancrew
