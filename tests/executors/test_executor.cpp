// One typed suite run against every threaded executor (rclcpp's habit), plus the
// behaviours that need several threads. Waits are bounded; nothing depends on timing
// beyond "eventually, within seconds".

#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <thread>

#include "executors/executor.hpp"
#include "executors/publisher.hpp"
#include "executors/subscription.hpp"
#include "executors/timer.hpp"
#include "tests/executors/test_messages.hpp"

namespace scancrew {
namespace {

using test::Counter;

constexpr int64_t kSecond = 1'000'000'000;

bool eventually(const std::function<bool()>& condition, int64_t timeout_ns = 10 * kSecond) {
  const int64_t give_up = monotonic_now_ns() + timeout_ns;
  while (!condition()) {
    if (monotonic_now_ns() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return true;
}

// Spins an executor on a background thread for the scope's lifetime.
class BackgroundSpin {
 public:
  explicit BackgroundSpin(Executor& e) : executor_(e), thread_([this] { executor_.spin(); }) {}
  ~BackgroundSpin() {
    executor_.stop();
    thread_.join();
  }

 private:
  Executor& executor_;
  std::thread thread_;
};

struct SingleThreaded {
  static std::unique_ptr<Executor> make() { return std::make_unique<SingleThreadedExecutor>(); }
};
struct MultiThreaded2 {
  static std::unique_ptr<Executor> make() { return std::make_unique<MultiThreadedExecutor>(2); }
};
struct MultiThreaded4 {
  static std::unique_ptr<Executor> make() { return std::make_unique<MultiThreadedExecutor>(4); }
};

template <class Maker>
class EveryExecutor : public ::testing::Test {
 protected:
  std::unique_ptr<Executor> executor_ = Maker::make();
  WallClock clock_;
  CallbackGroup group_{"g", CallbackGroup::Type::kMutuallyExclusive};
  std::shared_ptr<Topic<Counter>> topic_ = std::make_shared<Topic<Counter>>("/c", 64);
  Publisher<Counter> pub_{topic_, 0, &clock_, nullptr};

  void publish(uint64_t value) {
    auto loan = pub_.loan();
    ASSERT_TRUE(loan);
    (*loan)->value = value;
    ASSERT_TRUE(pub_.publish(std::move(*loan)));
  }
};

using Executors = ::testing::Types<SingleThreaded, MultiThreaded2, MultiThreaded4>;
TYPED_TEST_SUITE(EveryExecutor, Executors);

TYPED_TEST(EveryExecutor, DeliversEverySampleInOrderToAMutuallyExclusiveSubscription) {
  std::mutex m;
  std::vector<uint64_t> got;
  Subscription<Counter> sub(
      this->topic_, {.depth = 64},
      [&](Sample<Counter>&& s) {
        std::lock_guard lock(m);
        got.push_back(s->value);
      },
      this->group_, nullptr);
  this->executor_->add(sub);
  {
    BackgroundSpin spin(*this->executor_);
    for (uint64_t i = 1; i <= 50; ++i) this->publish(i);
    ASSERT_TRUE(eventually([&] {
      std::lock_guard lock(m);
      return got.size() == 50;
    }));
  }
  this->executor_->remove(sub);
  for (uint64_t i = 0; i < 50; ++i) EXPECT_EQ(got[i], i + 1);
}

TYPED_TEST(EveryExecutor, WallTimerFiresRepeatedly) {
  std::atomic<int> fired{0};
  Timer timer(
      this->clock_, 2'000'000, [&] { fired.fetch_add(1); }, this->group_, nullptr);
  this->executor_->add(timer);
  {
    BackgroundSpin spin(*this->executor_);
    EXPECT_TRUE(eventually([&] { return fired.load() >= 5; }));
  }
  this->executor_->remove(timer);
}

TYPED_TEST(EveryExecutor, SimTimerFiresOnlyWhenSimTimeReachesItsDeadline) {
  SimClock sim;
  std::atomic<int> fired{0};
  Timer timer(
      sim, 100, [&] { fired.fetch_add(1); }, this->group_, nullptr);
  this->executor_->add(timer);
  {
    BackgroundSpin spin(*this->executor_);
    sim.advance_to(99);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(fired.load(), 0);  // not due: sim time stands still however long we wait
    sim.advance_to(100);
    EXPECT_TRUE(eventually([&] { return fired.load() == 1; }));
    sim.advance_to(250);  // two periods passed: one firing, missed periods are skipped
    EXPECT_TRUE(eventually([&] { return fired.load() == 2; }));
    sim.advance_to(299);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(fired.load(), 2);
  }
  this->executor_->remove(timer);
}

TYPED_TEST(EveryExecutor, DisabledExecutablesDoNotRunUntilEnabled) {
  std::atomic<bool> active{false};
  std::atomic<int> calls{0};
  Subscription<Counter> sub(
      this->topic_, {.depth = 8}, [&](Sample<Counter>&&) { calls.fetch_add(1); }, this->group_,
      &active);
  this->executor_->add(sub);
  {
    BackgroundSpin spin(*this->executor_);
    this->publish(1);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    EXPECT_EQ(calls.load(), 0);
    active.store(true);
    this->executor_->wake();
    EXPECT_TRUE(eventually([&] { return calls.load() == 1; }));
  }
  this->executor_->remove(sub);
}

TYPED_TEST(EveryExecutor, StopBeforeSpinMakesSpinReturn) {
  this->executor_->stop();
  std::atomic<bool> returned{false};
  std::thread spinner([&] {
    this->executor_->spin();  // must not block
    returned.store(true);
  });
  const bool ok = eventually([&] { return returned.load(); });
  if (!ok) this->executor_->stop();  // a stop during spin, so that the thread can be joined
  spinner.join();
  EXPECT_TRUE(ok) << "spin() did not return after an earlier stop()";
}

TYPED_TEST(EveryExecutor, SpinOnceWaitsAtMostItsTimeout) {
  const int64_t t0 = monotonic_now_ns();
  EXPECT_FALSE(this->executor_->spin_once(5'000'000));
  EXPECT_GE(monotonic_now_ns() - t0, 5'000'000);
  Subscription<Counter> sub(
      this->topic_, {.depth = 8}, [](Sample<Counter>&&) {}, this->group_, nullptr);
  this->executor_->add(sub);
  this->publish(1);
  EXPECT_TRUE(this->executor_->spin_once(kSecond));
  this->executor_->remove(sub);
}

// --- several threads ---

TEST(MultiThreadedExecutor, MutuallyExclusiveCallbacksNeverOverlap) {
  WallClock clock;
  CallbackGroup group("mx", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = std::make_shared<Topic<Counter>>("/c", 64);
  Publisher<Counter> pub(topic, 0, &clock, nullptr);
  std::atomic<int> inside{0}, max_inside{0}, calls{0};
  auto body = [&](Sample<Counter>&&) {
    const int now = inside.fetch_add(1) + 1;
    int prev = max_inside.load();
    while (now > prev && !max_inside.compare_exchange_weak(prev, now)) {
    }
    std::this_thread::sleep_for(std::chrono::microseconds(300));
    inside.fetch_sub(1);
    calls.fetch_add(1);
  };
  Subscription<Counter> a(topic, {.depth = 32}, body, group, nullptr);
  Subscription<Counter> b(topic, {.depth = 32}, body, group, nullptr);
  MultiThreadedExecutor executor(4);
  executor.add(a);
  executor.add(b);
  {
    BackgroundSpin spin(executor);
    for (int i = 0; i < 20; ++i) ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
    ASSERT_TRUE(eventually([&] { return calls.load() == 40; }));
  }
  executor.remove(a);
  executor.remove(b);
  EXPECT_EQ(max_inside.load(), 1);
}

TEST(MultiThreadedExecutor, ReentrantCallbacksRunConcurrently) {
  // Two samples, one reentrant subscription: each callback waits (bounded) until both
  // are inside at once, which only concurrent execution allows.
  WallClock clock;
  CallbackGroup group("re", CallbackGroup::Type::kReentrant);
  auto topic = std::make_shared<Topic<Counter>>("/c", 8);
  Publisher<Counter> pub(topic, 0, &clock, nullptr);
  std::atomic<int> inside{0}, met{0}, calls{0};
  Subscription<Counter> sub(
      topic, {.depth = 8},
      [&](Sample<Counter>&&) {
        inside.fetch_add(1);
        if (eventually([&] { return inside.load() >= 2; }, 5 * kSecond)) met.fetch_add(1);
        calls.fetch_add(1);
      },
      group, nullptr);
  MultiThreadedExecutor executor(2);
  executor.add(sub);
  {
    BackgroundSpin spin(executor);
    ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
    ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
    ASSERT_TRUE(eventually([&] { return calls.load() == 2; }));
  }
  executor.remove(sub);
  EXPECT_EQ(met.load(), 2);
}

TEST(MultiThreadedExecutor, ABusyMutuallyExclusiveGroupDoesNotBlockOtherGroups) {
  WallClock clock;
  CallbackGroup slow_group("slow", CallbackGroup::Type::kMutuallyExclusive);
  CallbackGroup fast_group("fast", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = std::make_shared<Topic<Counter>>("/c", 8);
  Publisher<Counter> pub(topic, 0, &clock, nullptr);
  std::atomic<bool> release{false};
  std::atomic<int> fast_calls{0};
  std::atomic<bool> slow_done{false};
  Subscription<Counter> slow(
      topic, {.depth = 4},
      [&](Sample<Counter>&&) {
        eventually([&] { return release.load(); }, 10 * kSecond);
        slow_done.store(true);
      },
      slow_group, nullptr);
  Subscription<Counter> fast(
      topic, {.depth = 4}, [&](Sample<Counter>&&) { fast_calls.fetch_add(1); }, fast_group,
      nullptr);
  MultiThreadedExecutor executor(2);
  executor.add(slow);
  executor.add(fast);
  {
    BackgroundSpin spin(executor);
    ASSERT_TRUE(pub.publish(std::move(*pub.loan())));
    EXPECT_TRUE(eventually([&] { return fast_calls.load() == 1; }));  // while slow is still inside
    EXPECT_FALSE(slow_done.load());
    release.store(true);
    EXPECT_TRUE(eventually([&] { return slow_done.load(); }));
  }
  executor.remove(slow);
  executor.remove(fast);
}

}  // namespace
}  // namespace scancrew
