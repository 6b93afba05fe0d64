#pragma once

// Publisher<T>: the writing end of a topic. loan() hands out a slot of the topic's pool
// (or LoanError::kPoolExhausted); publish() stamps the header (robot id, sequence
// number, stamp if the writer left it unset, monotonic publish time) and delivers the
// slot to every subscription without copying it.
// Thread safety: loan() and publish() may be called from any thread; sequence numbers
// are unique per publisher. Allocation: none.

#include <atomic>
#include <memory>

#include "executors/clock.hpp"
#include "executors/topic.hpp"

namespace scancrew {

template <Message T>
class Publisher {
 public:
  Publisher() = default;
  Publisher(std::shared_ptr<Topic<T>> topic, uint32_t robot_id, const Clock* clock,
            const std::atomic<bool>* active)
      : topic_(std::move(topic)), robot_id_(robot_id), clock_(clock), active_(active) {}

  bool valid() const { return topic_ != nullptr; }

  Result<Loan<T>, LoanError> loan() {
    SCANCREW_CHECK(valid(), "loan() on a publisher that was never created");
    return topic_->loan();
  }

  Result<size_t, PublishError> publish(Loan<T>&& loan) {
    SCANCREW_CHECK(valid(), "publish() on a publisher that was never created");
    if (!loan.valid()) return make_unexpected(PublishError::kInvalidLoan);
    if (active_ != nullptr && !active_->load(std::memory_order_acquire)) {
      Loan<T> dropped = std::move(loan);
      return make_unexpected(PublishError::kInactive);
    }
    msg::Header& header = loan->header;
    header.robot_id = robot_id_;
    header.seq = seq_->fetch_add(1, std::memory_order_relaxed) + 1;
    if (header.stamp_ns == msg::kStampUnset) header.stamp_ns = clock_->now_ns();
    header.publish_mono_ns = monotonic_now_ns();
    return topic_->publish(std::move(loan));
  }

  // Publishes keeping the robot id, sequence number and stamp the loan carries: for replay
  // and for links that pass on another robot's messages. Sets publish_mono_ns only.
  Result<size_t, PublishError> forward(Loan<T>&& loan) {
    SCANCREW_CHECK(valid(), "forward() on a publisher that was never created");
    if (!loan.valid()) return make_unexpected(PublishError::kInvalidLoan);
    if (active_ != nullptr && !active_->load(std::memory_order_acquire)) {
      Loan<T> dropped = std::move(loan);
      return make_unexpected(PublishError::kInactive);
    }
    loan->header.publish_mono_ns = monotonic_now_ns();
    return topic_->publish(std::move(loan));
  }

  const std::string& topic_name() const { return topic_->name(); }
  // The robot id publish() stamps: the component's by default; a component that publishes
  // on behalf of robots (the simulator, a bridge) sets theirs.
  void set_robot_id(uint32_t robot_id) { robot_id_ = robot_id; }
  Topic<T>& topic() { return *topic_; }

 private:
  std::shared_ptr<Topic<T>> topic_;
  uint32_t robot_id_ = 0;
  const Clock* clock_ = nullptr;
  const std::atomic<bool>* active_ = nullptr;
  // boxed so the publisher stays movable
  std::unique_ptr<std::atomic<uint64_t>> seq_ = std::make_unique<std::atomic<uint64_t>>(0);
};

}  // namespace scancrew
