// StepExecutor with compute charged: a callback's CPU time becomes sim time on its place.
// Tolerances: the charged delay of a callback that burns X of CPU is X plus what the
// executor's own bookkeeping and the clock reads cost (microseconds), so 5 ms absolute.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

#include "executors/compute_clock.hpp"
#include "executors/publisher.hpp"
#include "executors/step_executor.hpp"
#include "executors/subscription.hpp"
#include "executors/timer.hpp"
#include "tests/executors/test_messages.hpp"

namespace scancrew {
namespace {

using test::Counter;
constexpr int64_t kMs = 1'000'000;
constexpr int64_t kTolerance = 5 * kMs;

// Spins on this thread until it has used `ns` of CPU time.
void burn_cpu(int64_t ns) {
  const int64_t until = ComputeClock::thread_cpu_ns() + ns;
  volatile uint64_t x = 0;
  while (ComputeClock::thread_cpu_ns() < until) x = x + 1;
}

// A fixed amount of arithmetic (not a fixed time): what a machine's load must not change.
uint64_t fixed_work(uint64_t iterations) {
  uint64_t h = 1469598103934665603ull;
  for (uint64_t i = 0; i < iterations; ++i) h = (h ^ i) * 1099511628211ull;
  return h;
}

// A world timer at 100 ms triggers; each worker (on the place given) computes, then
// publishes; a world sink logs when each output arrives.
struct Rig {
  SimClock clock;
  StepExecutor executor{clock};
  CallbackGroup group{"g", CallbackGroup::Type::kReentrant};
  std::shared_ptr<Topic<Counter>> trigger = std::make_shared<Topic<Counter>>("/trigger", 8);
  std::shared_ptr<Topic<Counter>> out = std::make_shared<Topic<Counter>>("/out", 8);
  Publisher<Counter> trigger_pub{trigger, 0, &clock, nullptr};
  std::unique_ptr<Timer> tick;
  std::vector<std::unique_ptr<Publisher<Counter>>> pubs;
  std::vector<std::unique_ptr<Subscription<Counter>>> workers;
  std::unique_ptr<Subscription<Counter>> sink;
  std::vector<std::pair<uint64_t, int64_t>> arrivals;  // (worker, sim time)

  explicit Rig(ComputeTime mode) {
    executor.set_compute_time(mode, {.scale = 1.0, .cores = 1});
    bool fired = false;
    tick = std::make_unique<Timer>(
        clock, 100 * kMs,
        [this, fired]() mutable {
          if (fired) return;
          fired = true;
          auto loan = trigger_pub.loan();
          (void)trigger_pub.publish(std::move(*loan));
        },
        group, nullptr);
    sink = std::make_unique<Subscription<Counter>>(
        out, SubscriptionQos{.depth = 8},
        [this](Sample<Counter>&& s) { arrivals.emplace_back(s->value, clock.now_ns()); }, group,
        nullptr);
  }

  // the executor outlives what it runs here: take them out first
  ~Rig() {
    for (auto& w : workers) executor.remove(*w);
    executor.remove(*tick);
    executor.remove(*sink);
  }
  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  void add_worker(int place, std::function<void()> compute) {
    const uint64_t id = workers.size();
    pubs.push_back(std::make_unique<Publisher<Counter>>(out, 1, &clock, nullptr));
    Publisher<Counter>* pub = pubs.back().get();
    workers.push_back(std::make_unique<Subscription<Counter>>(
        trigger, SubscriptionQos{.depth = 8},
        [pub, id, compute](Sample<Counter>&&) {
          compute();
          auto loan = pub->loan();
          (*loan)->value = id;
          (void)pub->publish(std::move(*loan));
        },
        group, nullptr));
    executor.add(*workers.back(), place);
  }

  void run(int64_t until_ns) {
    executor.add(*tick);
    executor.add(*sink);
    executor.run_until(until_ns);
  }

  int64_t arrival_of(uint64_t worker) const {
    for (const auto& [w, t] : arrivals)
      if (w == worker) return t;
    return -1;
  }
};

TEST(ChargedTime, AComponentThatComputesFor200msDelaysItsOutputBy200msOfSimTime) {
  Rig rig(ComputeTime::kCharged);
  rig.add_worker(rig.executor.add_place("r1"), [] { burn_cpu(200 * kMs); });
  rig.run(1000 * kMs);
  ASSERT_EQ(rig.arrivals.size(), 1u);
  EXPECT_GE(rig.arrival_of(0), 300 * kMs);
  EXPECT_LE(rig.arrival_of(0), 300 * kMs + kTolerance);
  const auto stats = rig.executor.place_stats();
  ASSERT_EQ(stats.size(), 1u);
  EXPECT_EQ(stats[0].callbacks, 1u);
  EXPECT_NEAR(stats[0].charged_s, 0.2, 0.005);
}

TEST(ChargedTime, FreeComputeDeliversAtOnce) {
  Rig rig(ComputeTime::kFree);
  rig.add_worker(rig.executor.add_place("r1"), [] { burn_cpu(50 * kMs); });
  rig.run(1000 * kMs);
  ASSERT_EQ(rig.arrivals.size(), 1u);
  EXPECT_EQ(rig.arrival_of(0), 100 * kMs);
}

TEST(ChargedTime, TwoPlacesComputeInParallel) {
  Rig rig(ComputeTime::kCharged);
  rig.add_worker(rig.executor.add_place("r1"), [] { burn_cpu(100 * kMs); });
  rig.add_worker(rig.executor.add_place("r2"), [] { burn_cpu(100 * kMs); });
  rig.run(1000 * kMs);
  ASSERT_EQ(rig.arrivals.size(), 2u);
  for (uint64_t w : {0u, 1u}) {
    EXPECT_GE(rig.arrival_of(w), 200 * kMs) << "worker " << w;
    EXPECT_LE(rig.arrival_of(w), 200 * kMs + kTolerance) << "worker " << w;
  }
}

TEST(ChargedTime, CallbacksWithinOnePlaceRunOneAfterTheOther) {
  Rig rig(ComputeTime::kCharged);
  const int place = rig.executor.add_place("station");
  rig.add_worker(place, [] { burn_cpu(100 * kMs); });
  rig.add_worker(place, [] { burn_cpu(100 * kMs); });
  rig.run(1000 * kMs);
  ASSERT_EQ(rig.arrivals.size(), 2u);
  const int64_t first = std::min(rig.arrival_of(0), rig.arrival_of(1));
  const int64_t second = std::max(rig.arrival_of(0), rig.arrival_of(1));
  EXPECT_NEAR(static_cast<double>(first), 200.0 * kMs, kTolerance);
  EXPECT_NEAR(static_cast<double>(second), 300.0 * kMs, 2 * kTolerance);
}

TEST(ChargedTime, ComputeScaleStretchesTheCharge) {
  Rig rig(ComputeTime::kCharged);
  rig.executor.set_compute_time(ComputeTime::kCharged, {.scale = 2.0, .cores = 1});
  rig.add_worker(rig.executor.add_place("r1"), [] { burn_cpu(50 * kMs); });
  rig.run(1000 * kMs);
  EXPECT_NEAR(static_cast<double>(rig.arrival_of(0)), 200.0 * kMs, 2 * kTolerance);
}

// The charge of one fixed piece of work, alone and with every core of this machine busy
// with other threads. CPU time barely moves with load (wall time would double or more):
// the stated tolerance is 25 %.
TEST(ChargedTime, TheChargeDoesNotDependOnHowLoadedTheMachineIs) {
  const auto charge_of_fixed_work = [] {
    Rig rig(ComputeTime::kCharged);
    rig.add_worker(rig.executor.add_place("r1"), [] {
      volatile uint64_t sink = fixed_work(60'000'000);
      (void)sink;
    });
    rig.run(10'000 * kMs);
    return static_cast<double>(rig.arrival_of(0) - 100 * kMs);
  };
  const double alone = charge_of_fixed_work();
  std::atomic<bool> stop{false};
  std::vector<std::thread> hogs;
  const unsigned cores = std::max(2u, std::thread::hardware_concurrency());
  for (unsigned i = 0; i < cores; ++i)
    hogs.emplace_back([&stop] {
      volatile uint64_t x = 0;
      while (!stop.load(std::memory_order_relaxed)) x = x + 1;
    });
  const double loaded = charge_of_fixed_work();
  stop = true;
  for (auto& t : hogs) t.join();
  ASSERT_GT(alone, 1e6);
  EXPECT_NEAR(loaded / alone, 1.0, 0.25)
      << "alone " << alone * 1e-6 << " ms, loaded " << loaded * 1e-6 << " ms";
}

// A place kept busy by a stream of inputs still runs its timer: its ready callbacks take
// turns when it is free.
TEST(ChargedTime, ABusyInputStreamDoesNotStarveATimerOfTheSamePlace) {
  SimClock clock;
  StepExecutor executor(clock);
  executor.set_compute_time(ComputeTime::kCharged, {.scale = 1.0, .cores = 1});
  CallbackGroup group("g", CallbackGroup::Type::kReentrant);
  auto topic = std::make_shared<Topic<Counter>>("/stream", 8);
  Publisher<Counter> pub(topic, 0, &clock, nullptr);
  Timer source(
      clock, kMs,
      [&] {
        auto loan = pub.loan();
        (void)pub.publish(std::move(*loan));
      },
      group, nullptr);
  uint64_t handled = 0, ticks = 0;
  Subscription<Counter> heavy(
      topic, {.depth = 4},
      [&](Sample<Counter>&&) {
        burn_cpu(2 * kMs);
        ++handled;
      },
      group, nullptr);
  Timer light(
      clock, 10 * kMs, [&] { ++ticks; }, group, nullptr);
  const int place = executor.add_place("r1");
  executor.add(source);
  executor.add(heavy, place);
  executor.add(light, place);
  executor.run_until(500 * kMs);
  // the stream alone would keep the place busy all the time (2 ms per 1 ms input)
  EXPECT_GT(handled, 150u);
  EXPECT_GT(ticks, 30u);
  for (Executable* e : std::initializer_list<Executable*>{&source, &heavy, &light})
    executor.remove(*e);
}

TEST(ChargedTime, ChargedNsSpreadsHelperThreadsOverTheCores) {
  EXPECT_EQ(charged_ns(100, 0, 2, 1.0), 100);    // serial work is not sped up
  EXPECT_EQ(charged_ns(100, 100, 2, 1.0), 100);  // 2 threads on 2 cores: their wall time
  EXPECT_EQ(charged_ns(100, 100, 1, 1.0), 200);  // on 1 core: their sum
  EXPECT_EQ(charged_ns(100, 300, 4, 1.0), 100);  // 4 cores: the sum / 4
  EXPECT_EQ(charged_ns(100, 0, 1, 0.5), 50);     // a faster computer
}

}  // namespace
}  // namespace scancrew
