#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "executors/publisher.hpp"
#include "executors/step_executor.hpp"
#include "executors/subscription.hpp"
#include "executors/timer.hpp"
#include "tests/executors/test_messages.hpp"

namespace scancrew {
namespace {

using test::Counter;

// A little pipeline on sim time: a 10 ms timer publishes; a subscriber republishes;
// a second subscriber logs. Returns the log of (sim time, event).
std::vector<std::string> run_pipeline(int64_t until_ns) {
  SimClock clock;
  CallbackGroup group("g", CallbackGroup::Type::kMutuallyExclusive);
  auto first = std::make_shared<Topic<Counter>>("/first", 8);
  auto second = std::make_shared<Topic<Counter>>("/second", 8);
  Publisher<Counter> pub1(first, 1, &clock, nullptr), pub2(second, 1, &clock, nullptr);
  std::vector<std::string> log;
  uint64_t n = 0;
  Timer timer(
      clock, 10'000'000,
      [&] {
        auto loan = pub1.loan();
        (*loan)->value = ++n;
        log.push_back(std::to_string(clock.now_ns()) + " tick " + std::to_string(n));
        (void)pub1.publish(std::move(*loan));
      },
      group, nullptr);
  Subscription<Counter> relay(
      first, {.depth = 4},
      [&](Sample<Counter>&& s) {
        auto loan = pub2.loan();
        (*loan)->value = s->value * 10;
        (*loan)->header.stamp_ns = s->header.stamp_ns;
        (void)pub2.publish(std::move(*loan));
      },
      group, nullptr);
  Subscription<Counter> sink(
      second, {.depth = 4},
      [&](Sample<Counter>&& s) {
        log.push_back(std::to_string(clock.now_ns()) + " got " + std::to_string(s->value) +
                      " stamped " + std::to_string(s->header.stamp_ns));
      },
      group, nullptr);
  StepExecutor executor(clock);
  executor.add(timer);
  executor.add(relay);
  executor.add(sink);
  executor.run_until(until_ns);
  EXPECT_EQ(clock.now_ns(), until_ns);
  return log;
}

TEST(StepExecutor, FiresTimersAtExactSimTimesAndDrainsChainsWithinTheStep) {
  const auto log = run_pipeline(35'000'000);
  const std::vector<std::string> expected = {
      "10000000 tick 1", "10000000 got 10 stamped 10000000",
      "20000000 tick 2", "20000000 got 20 stamped 20000000",
      "30000000 tick 3", "30000000 got 30 stamped 30000000",
  };
  EXPECT_EQ(log, expected);
}

TEST(StepExecutor, TwoRunsGiveTheSameSequenceOfCallbacks) {
  EXPECT_EQ(run_pipeline(1'000'000'000), run_pipeline(1'000'000'000));
}

TEST(StepExecutor, RunUntilInSmallStepsEqualsOneBigStep) {
  SimClock clock;
  CallbackGroup group("g", CallbackGroup::Type::kMutuallyExclusive);
  std::vector<int64_t> fired_at;
  Timer timer(
      clock, 7, [&] { fired_at.push_back(clock.now_ns()); }, group, nullptr);
  StepExecutor executor(clock);
  executor.add(timer);
  for (int64_t t = 3; t <= 30; t += 3) executor.run_until(t);
  EXPECT_EQ(fired_at, (std::vector<int64_t>{7, 14, 21, 28}));
}

TEST(StepExecutorDeathTest, RejectsWallClockTimers) {
  SimClock sim;
  WallClock wall;
  CallbackGroup group("g", CallbackGroup::Type::kMutuallyExclusive);
  Timer timer(
      wall, 1'000'000, [] {}, group, nullptr);
  StepExecutor executor(sim);
  EXPECT_DEATH(executor.add(timer), "sim time only");
}

}  // namespace
}  // namespace scancrew
