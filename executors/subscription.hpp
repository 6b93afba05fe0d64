#pragma once

// Subscription<T>: a bounded queue on a topic plus the callback an executor runs for
// each sample. The callback receives a read-only Sample<T> on the publisher's slot (no
// copy) and may keep it; the slot stays out of the pool while it is held.
// Thread safety: see Executable. Latency (publish -> callback start) is recorded per
// sample in the queue's histogram. Allocation: none after construction.

#include <functional>
#include <memory>

#include "executors/executable.hpp"
#include "executors/topic.hpp"

namespace scancrew {

template <Message T>
class Subscription final : public Executable {
 public:
  using Callback = std::function<void(Sample<T>&&)>;

  Subscription(std::shared_ptr<Topic<T>> topic, SubscriptionQos qos, Callback callback,
               CallbackGroup& group, const std::atomic<bool>* active)
      : Executable(group, active),
        topic_(std::move(topic)),
        queue_(qos),
        callback_(std::move(callback)) {
    SCANCREW_CHECK(qos.depth > 0, "subscription depth must be positive");
    set_trace_what(topic_->name());
    topic_->attach(queue_);
  }
  ~Subscription() override { topic_->detach(queue_); }

  bool has_work() const override { return queue_.size() > 0; }

  bool execute() override {
    Sample<T> sample = topic_->take(queue_);
    if (!sample.valid()) return false;
    queue_.latency.record(monotonic_now_ns() - sample->header.publish_mono_ns);
    queue_.taken.fetch_add(1, std::memory_order_relaxed);
    callback_(std::move(sample));
    return true;
  }

  void set_wake_target(WakeTarget* target) override { queue_.set_wake_target(target); }

  const Topic<T>& topic() const { return *topic_; }
  const SubscriberQueue& queue() const { return queue_; }

 private:
  std::shared_ptr<Topic<T>> topic_;
  SubscriberQueue queue_;
  Callback callback_;
};

}  // namespace scancrew
