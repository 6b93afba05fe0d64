// Tracing: the per-component totals and the timeline events the executors record, the
// Chrome trace they write (parsed back), a full buffer, a disabled tracer, and a
// multi-threaded run. Ends with a microbenchmark of the cost per callback (printed only).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "executors/executor.hpp"
#include "executors/launch.hpp"
#include "executors/publisher.hpp"
#include "executors/step_executor.hpp"
#include "executors/subscription.hpp"
#include "executors/timer.hpp"
#include "executors/trace.hpp"
#include "tests/executors/test_components.hpp"

namespace scancrew {
namespace {

using test::Counter;

// Two robots, each a talker (100 ms sim timer) and a listener, plus one team listener of
// robot2's talker: 1 s of sim time runs 10 callbacks of each of the five components.
constexpr const char* kTeam = R"(
clock: sim
executor: {type: step}
run: {duration_s: 1.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1}
  - {id: 2, namespace: r2}
components:
  - {name: talker, type: test_talker, params: {period_s: 0.1}, remap: {out: chatter}}
  - {name: listener, type: test_listener, remap: {in: chatter}}
  - {name: team_listener, type: test_listener, per_robot: false, remap: {in: /r2/chatter}}
)";

std::unique_ptr<Launch> run_team(size_t max_events) {
  auto launch = Launch::from_string(kTeam, "team.yaml");
  EXPECT_TRUE(launch) << launch.error().front();
  if (!launch) return nullptr;
  (*launch)->enable_tracing(max_events);
  EXPECT_DOUBLE_EQ((*launch)->run(), 1.0);
  return std::move(launch).value();
}

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("scancrew_test_trace_" + std::to_string(::getpid()) + "_" + name);
}

nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);  // throws (fails the test) on malformed JSON
}

TEST(Tracer, IsOffUnlessTheLaunchEnablesIt) {
  auto launch = Launch::from_string(kTeam, "team.yaml");
  ASSERT_TRUE(launch);
  EXPECT_EQ((*launch)->tracer(), nullptr);
  (void)(*launch)->run();
  EXPECT_EQ((*launch)->tracer(), nullptr);
}

TEST(Tracer, StepLaunchCountsEveryCallbackOfEachComponent) {
  auto launch = run_team(1000);
  ASSERT_TRUE(launch);
  const Tracer& tracer = *launch->tracer();
  const auto times = tracer.component_times();
  std::map<std::string, uint64_t> callbacks;
  for (const auto& t : times) {
    callbacks[t.component] = t.callbacks;
    EXPECT_GE(t.total_ms, 0.0) << t.component;
    EXPECT_LE(t.p50_ms, t.p99_ms) << t.component;
    EXPECT_LE(t.p50_ms, t.total_ms) << t.component;
  }
  EXPECT_EQ(callbacks, (std::map<std::string, uint64_t>{{"r1/talker", 10},
                                                        {"r1/listener", 10},
                                                        {"r2/talker", 10},
                                                        {"r2/listener", 10},
                                                        {"team_listener", 10}}));
  for (size_t i = 1; i < times.size(); ++i) EXPECT_GE(times[i - 1].total_ms, times[i].total_ms);
  EXPECT_EQ(tracer.dropped_events(), 0u);
}

TEST(Tracer, EventsNameTheirComponentAndTopicOrTimer) {
  auto launch = run_team(1000);
  ASSERT_TRUE(launch);
  const Tracer& tracer = *launch->tracer();
  ASSERT_EQ(tracer.event_count(), 50u);
  std::map<std::string, std::set<std::string>> what;
  int64_t previous_start = 0;
  for (const TraceEvent& e : tracer.events()) {
    EXPECT_GE(e.duration_ns, 0);
    EXPECT_GE(e.start_ns, previous_start);  // one thread: in the order they ran
    previous_start = e.start_ns + e.duration_ns;
    EXPECT_GE(e.thread, 1u);
    what[tracer.source_component(e.source)].insert(tracer.source_what(e.source));
  }
  EXPECT_EQ(what,
            (std::map<std::string, std::set<std::string>>{{"r1/talker", {"timer 100ms"}},
                                                          {"r1/listener", {"/r1/chatter"}},
                                                          {"r2/talker", {"timer 100ms"}},
                                                          {"r2/listener", {"/r2/chatter"}},
                                                          {"team_listener", {"/r2/chatter"}}}));
}

TEST(Tracer, WritesAChromeTraceWithOneProcessPerNamespace) {
  auto launch = run_team(1000);
  ASSERT_TRUE(launch);
  const auto path = temp_file("trace.json");
  ASSERT_TRUE(launch->tracer()->write_chrome_trace(path.string()));
  const nlohmann::json trace = read_json(path);
  std::filesystem::remove(path);

  EXPECT_EQ(trace.at("displayTimeUnit"), "ms");
  EXPECT_EQ(trace.at("otherData").at("dropped_events"), 0);
  std::map<int, std::string> process_names;
  std::set<std::pair<int, int>> named_threads, used_threads;
  std::map<std::string, int> pid_of, complete;
  for (const auto& e : trace.at("traceEvents")) {
    const std::string ph = e.at("ph");
    if (ph == "M" && e.at("name") == "process_name") {
      process_names[e.at("pid")] = e.at("args").at("name");
    } else if (ph == "M" && e.at("name") == "thread_name") {
      named_threads.emplace(e.at("pid"), e.at("tid"));
      EXPECT_FALSE(e.at("args").at("name").get<std::string>().empty());
    } else {
      ASSERT_EQ(ph, "X");
      const std::string name = e.at("name");
      ++complete[name];
      pid_of[name] = e.at("pid");
      used_threads.emplace(e.at("pid"), e.at("tid"));
      EXPECT_GE(e.at("ts").get<double>(), 0.0);
      EXPECT_GE(e.at("dur").get<double>(), 0.0);
      EXPECT_TRUE(e.at("cat").get<std::string>() == "timer 100ms" ||
                  e.at("cat").get<std::string>().starts_with("/r"));
    }
  }
  EXPECT_EQ(complete, (std::map<std::string, int>{{"r1/talker", 10},
                                                  {"r1/listener", 10},
                                                  {"r2/talker", 10},
                                                  {"r2/listener", 10},
                                                  {"team_listener", 10}}));
  ASSERT_EQ(process_names.size(), 3u);
  EXPECT_EQ(process_names[pid_of["r1/talker"]], "r1");
  EXPECT_EQ(process_names[pid_of["r1/listener"]], "r1");
  EXPECT_EQ(process_names[pid_of["r2/talker"]], "r2");
  EXPECT_EQ(process_names[pid_of["team_listener"]], "team");
  EXPECT_EQ(named_threads, used_threads);
}

TEST(Tracer, AFullBufferCountsTheEventsItDropsAndKeepsTheTotals) {
  auto launch = run_team(8);
  ASSERT_TRUE(launch);
  const Tracer& tracer = *launch->tracer();
  EXPECT_EQ(tracer.event_count(), 8u);
  EXPECT_EQ(tracer.dropped_events(), 42u);
  uint64_t callbacks = 0;
  for (const auto& t : tracer.component_times()) callbacks += t.callbacks;
  EXPECT_EQ(callbacks, 50u);

  const auto path = temp_file("full.json");
  ASSERT_TRUE(tracer.write_chrome_trace(path.string()));
  const nlohmann::json trace = read_json(path);
  std::filesystem::remove(path);
  EXPECT_EQ(trace.at("otherData").at("dropped_events"), 42);
  size_t complete = 0;
  for (const auto& e : trace.at("traceEvents")) complete += e.at("ph") == "X" ? 1 : 0;
  EXPECT_EQ(complete, 8u);
}

TEST(Tracer, AnUnwritablePathIsAnErrorNamingIt) {
  Tracer tracer(4);
  const std::string path = "/nonexistent_dir_of_scancrew/trace.json";
  auto written = tracer.write_chrome_trace(path);
  ASSERT_FALSE(written);
  EXPECT_NE(written.error().find(path), std::string::npos) << written.error();
}

TEST(Tracer, ADisabledTracerRecordsNothing) {
  SimClock clock;
  CallbackGroup group("solo", CallbackGroup::Type::kMutuallyExclusive);
  int fired = 0;
  Timer timer(
      clock, 1'000'000, [&] { ++fired; }, group, nullptr);
  StepExecutor executor(clock);
  executor.add(timer);
  Tracer tracer(100);
  executor.set_tracer(&tracer);
  tracer.set_enabled(false);
  executor.run_until(10'000'000);
  EXPECT_EQ(fired, 10);
  EXPECT_EQ(tracer.event_count(), 0u);
  EXPECT_EQ(tracer.dropped_events(), 0u);
  ASSERT_EQ(tracer.component_times().size(), 1u);
  EXPECT_EQ(tracer.component_times()[0].component, "solo");  // named by its group
  EXPECT_EQ(tracer.component_times()[0].callbacks, 0u);

  tracer.set_enabled(true);
  executor.run_until(15'000'000);
  EXPECT_EQ(tracer.event_count(), 5u);
  EXPECT_EQ(tracer.component_times()[0].callbacks, 5u);
  EXPECT_EQ(tracer.source_what(tracer.events()[0].source), "timer 1ms");
}

// Publishes n counters from this thread while `executor` spins on others; waits until
// `done` says every callback ran (bounded).
void publish_and_wait(Publisher<Counter>& pub, int n, const std::function<bool()>& done) {
  const int64_t give_up = monotonic_now_ns() + 20'000'000'000;
  for (int i = 0; i < n; ++i) {
    auto loan = pub.loan();
    while (!loan && monotonic_now_ns() < give_up) {  // slots still held by queues
      std::this_thread::yield();
      loan = pub.loan();
    }
    ASSERT_TRUE(loan);
    (*loan)->value = static_cast<uint64_t>(i);
    ASSERT_TRUE(pub.publish(std::move(*loan)));
  }
  while (!done() && monotonic_now_ns() < give_up) std::this_thread::yield();
  ASSERT_TRUE(done());
}

TEST(Tracer, MultiThreadedRunTotalsEqualTheCallbacksRun) {
  for (const size_t capacity : {size_t{100'000}, size_t{100}}) {
    WallClock clock;
    CallbackGroup reentrant("shared", CallbackGroup::Type::kReentrant);
    CallbackGroup b_group("r2/b", CallbackGroup::Type::kMutuallyExclusive);
    auto topic = std::make_shared<Topic<Counter>>("/c", 16);
    Publisher<Counter> pub(topic, 0, &clock, nullptr);
    constexpr int kSamples = 400;
    std::atomic<int> a_got{0}, b_got{0};
    Subscription<Counter> a1(
        topic, {.depth = kSamples}, [&](Sample<Counter>&&) { a_got.fetch_add(1); }, reentrant,
        nullptr);
    Subscription<Counter> a2(
        topic, {.depth = kSamples}, [&](Sample<Counter>&&) { a_got.fetch_add(1); }, reentrant,
        nullptr);
    Subscription<Counter> b(
        topic, {.depth = kSamples}, [&](Sample<Counter>&&) { b_got.fetch_add(1); }, b_group,
        nullptr);
    Timer tick(
        clock, 200'000, [] {}, b_group, nullptr);
    a1.set_trace_component("r1/a");
    a2.set_trace_component("r1/a");
    b.set_trace_component("r2/b");
    tick.set_trace_component("r2/b");
    MultiThreadedExecutor executor(3);
    Tracer tracer(capacity);
    executor.set_tracer(&tracer);
    for (Executable* e : std::initializer_list<Executable*>{&a1, &a2, &b, &tick}) executor.add(*e);
    std::thread spinner([&] { executor.spin(); });
    publish_and_wait(pub, kSamples, [&] { return a_got == 2 * kSamples && b_got == kSamples; });
    executor.stop();
    spinner.join();
    for (Executable* e : std::initializer_list<Executable*>{&a1, &a2, &b, &tick})
      executor.remove(*e);

    std::map<std::string, uint64_t> callbacks;
    uint64_t total = 0;
    for (const auto& t : tracer.component_times()) {
      callbacks[t.component] = t.callbacks;
      total += t.callbacks;
    }
    EXPECT_EQ(callbacks["r1/a"], 2u * kSamples);
    EXPECT_EQ(callbacks["r2/b"], kSamples + tick.fire_count());
    EXPECT_EQ(total, executor.executed());
    EXPECT_EQ(tracer.event_count() + tracer.dropped_events(), total);
    EXPECT_EQ(tracer.event_count(), std::min<uint64_t>(capacity, total));
    for (const TraceEvent& e : tracer.events()) {
      EXPECT_GE(e.duration_ns, 0);
      EXPECT_GE(e.start_ns, 0);
    }
  }
}

// Not a test of speed (nothing is asserted on time): prints the cost per callback of a
// one-thread publish -> callback round without a tracer, with one, and with a disabled one.
TEST(Tracer, MicrobenchmarkPrintsTheCostPerCallback) {
  WallClock clock;
  CallbackGroup group("bench", CallbackGroup::Type::kMutuallyExclusive);
  auto topic = std::make_shared<Topic<Counter>>("/bench", 4);
  Publisher<Counter> pub(topic, 0, &clock, nullptr);
  uint64_t sum = 0;
  Subscription<Counter> sub(
      topic, {.depth = 2}, [&](Sample<Counter>&& s) { sum += s->value; }, group, nullptr);
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  constexpr int kRounds = 20'000;  // the figures mean nothing under a sanitizer
#else
  constexpr int kRounds = 200'000;
#endif
  const auto measure = [&](Executor& executor) {
    const int64_t start = monotonic_now_ns();
    for (int i = 0; i < kRounds; ++i) {
      auto loan = pub.loan();
      (*loan)->value = 1;
      (void)pub.publish(std::move(*loan));
      executor.spin_some();
    }
    return static_cast<double>(monotonic_now_ns() - start) / kRounds;
  };
  double best[4] = {1e18, 1e18, 1e18, 1e18};
  size_t recorded = 0;
  for (int repeat = 0; repeat < 3; ++repeat) {
    Tracer on(kRounds), off_flag(kRounds), full(0);  // on: room for every event
    off_flag.set_enabled(false);
    Tracer* tracers[4] = {nullptr, &on, &off_flag, &full};
    for (int k = 0; k < 4; ++k) {
      SingleThreadedExecutor executor;
      executor.add(sub);
      executor.set_tracer(tracers[k]);
      best[k] = std::min(best[k], measure(executor));
      executor.remove(sub);
    }
    recorded += on.event_count() + off_flag.event_count() + full.event_count();
  }
  std::printf(
      "publish->callback round, one thread, best of 3 x %d: no tracer %.1f ns, tracing on "
      "%.1f ns, tracer disabled %.1f ns, tracing on with a full buffer %.1f ns\n",
      kRounds, best[0], best[1], best[2], best[3]);
  EXPECT_EQ(sum, 12u * kRounds);
  EXPECT_EQ(recorded, 3u * kRounds);
}

}  // namespace
}  // namespace scancrew
