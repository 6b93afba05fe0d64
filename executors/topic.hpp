#pragma once

// Topic<T>: a named, typed channel inside one process. It owns the pool of slots that
// publishers loan from and the list of subscriber queues it delivers to.
//
// Delivery (publish): under the topic mutex, the slot index is pushed into every
// subscriber queue, each push taking one reference on the slot; then the publisher's
// reference is dropped. Nothing is copied. Overflow follows each queue's History:
// keep-last evicts the oldest entry (a counted drop), fail-fast rejects the publish for
// everyone (counted, reported to the caller). A publish on a thread with a PublishDeferral
// installed is delivered later, when the deferral's owner says (a fail-fast rejection is
// then counted but not reported to the publisher).
//
// Thread safety: every member function may be called from any thread. Lock order:
// topic mutex, then pool mutex, then an executor's wake mutex.
// Allocation: attach()/detach() and construction allocate; loan/publish/take do not.

#include <algorithm>
#include <atomic>
#include <concepts>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"
#include "executors/latency_histogram.hpp"
#include "executors/sample.hpp"
#include "executors/subscriber_queue.hpp"
#include "interfaces/header.hpp"

namespace scancrew {

// A message type: a plain struct with a header and a stable type name.
template <class T>
concept Message = requires(T t) {
  { t.header } -> std::same_as<msg::Header&>;
  { T::kTypeName } -> std::convertible_to<std::string_view>;
};

enum class LoanError { kPoolExhausted };
enum class PublishError { kQueueFull, kInvalidLoan, kInactive };
std::string_view to_string(LoanError error);
std::string_view to_string(PublishError error);

struct TopicStats {
  std::string name;
  std::string type_name;
  size_t pool_size = 0;
  size_t pool_available = 0;
  size_t subscriptions = 0;
  uint64_t published = 0;
  uint64_t loan_failures = 0;  // loan() found the pool empty
  uint64_t rejected = 0;       // fail-fast publishes refused
  uint64_t dropped = 0;        // keep-last evictions, over all subscriptions
  uint64_t taken = 0;          // samples handed to callbacks, over all subscriptions
  double rate_hz = 0.0;        // publish rate between first and last publish
  uint64_t latency_p50_ns = 0, latency_p99_ns = 0, latency_max_ns = 0;  // publish -> callback
};

// PublishDeferral: while one is installed on a thread (Scope), what that thread publishes is
// not delivered: the topic hands the published slot (with the publisher's reference) to
// defer(), and whoever installed it calls TopicBase::deliver() later, or discard(). The step
// executor uses it to make a charged callback's outputs appear when its compute is over
// (StepExecutor, compute_time: charged). Thread safety: per thread; defer() is called on
// the installing thread.
class TopicBase;
class PublishDeferral {
 public:
  virtual ~PublishDeferral() = default;
  virtual void defer(TopicBase& topic, uint32_t index) = 0;
  // The deferral installed on the calling thread, or null.
  static PublishDeferral* current();

  class Scope {
   public:
    explicit Scope(PublishDeferral* deferral);
    ~Scope();
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    PublishDeferral* previous_;
  };
};

class TopicBase {
 public:
  TopicBase(std::string name, std::string_view type_name, const void* type_tag)
      : name_(std::move(name)), type_name_(type_name), type_tag_(type_tag) {}
  virtual ~TopicBase() = default;
  TopicBase(const TopicBase&) = delete;
  TopicBase& operator=(const TopicBase&) = delete;

  const std::string& name() const { return name_; }
  const std::string& type_name() const { return type_name_; }
  const void* type_tag() const { return type_tag_; }
  virtual TopicStats stats() const = 0;
  // A deferred publish (PublishDeferral): delivers the slot to the queues attached now, or
  // drops it; either consumes the reference defer() was given.
  virtual void deliver(uint32_t index) = 0;
  virtual void discard(uint32_t index) = 0;

 protected:
  void note_publish(int64_t mono_ns) {
    int64_t unset = 0;
    first_publish_ns_.compare_exchange_strong(unset, mono_ns, std::memory_order_relaxed);
    last_publish_ns_.store(mono_ns, std::memory_order_relaxed);
    published_.fetch_add(1, std::memory_order_relaxed);
  }
  TopicStats base_stats() const;

  std::string name_;
  std::string type_name_;
  const void* type_tag_;
  std::atomic<uint64_t> published_{0}, loan_failures_{0}, rejected_{0};
  std::atomic<int64_t> first_publish_ns_{0}, last_publish_ns_{0};
};

// A unique address per message type, to tell types apart without RTTI.
template <class T>
const void* message_type_tag() {
  static const char tag = 0;
  return &tag;
}

template <Message T>
class Topic final : public TopicBase {
 public:
  Topic(std::string name, size_t pool_size)
      : TopicBase(std::move(name), T::kTypeName, message_type_tag<T>()), pool_(pool_size) {}
  ~Topic() override { SCANCREW_CHECK(queues_.empty(), "a subscription outlived its topic"); }

  Result<Loan<T>, LoanError> loan() {
    const auto index = pool_.acquire();
    if (!index) {
      loan_failures_.fetch_add(1, std::memory_order_relaxed);
      return make_unexpected(LoanError::kPoolExhausted);
    }
    Loan<T> loan(&pool_, *index);
    loan->header = msg::Header{};
    return loan;
  }

  // Delivers the loaned slot to every attached queue. Returns the number of queues that
  // received it. The loan is consumed whatever the outcome.
  Result<size_t, PublishError> publish(Loan<T>&& loan) {
    if (!loan.valid() || loan.pool() != &pool_) {
      Loan<T> dropped = std::move(loan);  // consumed: a foreign slot goes back to its own pool
      return make_unexpected(PublishError::kInvalidLoan);
    }
    const uint32_t index = loan.release_to_publish();
    note_publish(pool_.at(index).header.publish_mono_ns);
    if (PublishDeferral* deferral = PublishDeferral::current()) {
      deferral->defer(*this, index);
      std::lock_guard lock(mutex_);
      return queues_.size();
    }
    return deliver_now(index);
  }

  void deliver(uint32_t index) override { (void)deliver_now(index); }
  void discard(uint32_t index) override { pool_.release(index); }

  // Takes the oldest sample of a queue, if any; the Sample adopts the queue's reference.
  Sample<T> take(SubscriberQueue& queue) {
    std::lock_guard lock(mutex_);
    if (queue.empty()) return {};
    return Sample<T>(&pool_, queue.pop());
  }

  void attach(SubscriberQueue& queue) {
    std::lock_guard lock(mutex_);
    queues_.push_back(&queue);
  }
  // Removes a queue and releases the samples it still holds.
  void detach(SubscriberQueue& queue) {
    std::lock_guard lock(mutex_);
    std::erase(queues_, &queue);
    while (!queue.empty()) pool_.release(queue.pop());
  }

  const SamplePool<T>& pool() const { return pool_; }

  TopicStats stats() const override {
    TopicStats s = base_stats();
    s.pool_size = pool_.capacity();
    s.pool_available = pool_.available();
    LatencyHistogram merged;
    std::lock_guard lock(mutex_);
    s.subscriptions = queues_.size();
    for (const SubscriberQueue* q : queues_) {
      s.dropped += q->dropped.load(std::memory_order_relaxed);
      s.taken += q->taken.load(std::memory_order_relaxed);
      merged.merge_from(q->latency);
    }
    s.latency_p50_ns = merged.percentile_ns(0.5);
    s.latency_p99_ns = merged.percentile_ns(0.99);
    s.latency_max_ns = merged.max_ns();
    return s;
  }

 private:
  // The publisher's reference on `index` is consumed.
  Result<size_t, PublishError> deliver_now(uint32_t index) {
    std::lock_guard lock(mutex_);
    for (SubscriberQueue* q : queues_) {
      if (q->qos().history == History::kFailFast && q->full()) {
        rejected_.fetch_add(1, std::memory_order_relaxed);
        pool_.release(index);
        return make_unexpected(PublishError::kQueueFull);
      }
    }
    for (SubscriberQueue* q : queues_) {
      if (q->full()) {
        pool_.release(q->pop());
        q->dropped.fetch_add(1, std::memory_order_relaxed);
      }
      pool_.retain(index);
      q->push(index);
      q->received.fetch_add(1, std::memory_order_relaxed);
    }
    pool_.release(index);
    for (SubscriberQueue* q : queues_) q->wake();
    return queues_.size();
  }

  SamplePool<T> pool_;
  mutable std::mutex mutex_;
  std::vector<SubscriberQueue*> queues_;
};

}  // namespace scancrew
