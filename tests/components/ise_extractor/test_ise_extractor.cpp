// The ise_extractor component's give-up rule on sim time: a robot stands at the viewpoint of
// one of the room's two ISEs (scenes.hpp) while the map comes at different rates. The ISE
// must be given up after the same time standing whatever the rate: a station's map updates
// once per robot's snapshot, a distributed robot's once more per teammate's patch, and the
// rule counted updates (the parking lot's 4 distributed robots: the last robot's map came
// half as often, it gave up 20 ISEs where its teammates gave up 36, and the mission waited
// ~60 s for it alone). Each arrival counts: a robot passing through the viewpoint between
// two updates of a slow clock would not.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "components/ise_extractor/ise_extractor.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "tests/core/ise/scenes.hpp"

namespace scancrew::ise_extractor {
namespace {

// Publishes the room's map every map_period_s (stamped now) and the robot's pose at the
// viewpoint of the ISE (0, 0, 0), (2.05, 0.05, 0.05) facing −x, every 50 ms; with
// blink_period_s > 0 the robot stands there for the first half of each period (shifted 0.1 s
// early) and 1.45 m aside for the second.
class RoomFeeder final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: the room's map and a standing robot";
  struct Config {
    double map_period_s = 1.0;
    double blink_period_s = 0;
    double skip_period_s = 0;
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional("map_period_s", c.map_period_s, {0.05, 10});
    p.optional("blink_period_s", c.blink_period_s, {0, 10});
    p.optional("skip_period_s", c.skip_period_s, {0, 10});
    return c;
  }
  RoomFeeder(ComponentContext c, Config config) : Component(std::move(c)), config_(config) {
    ise::test::build_room(scene_);
  }

 private:
  Result<void, std::string> on_configure() override {
    map_ = create_publisher<msg::MapUpdate>("map", {.pool_size = 2});
    pose_ = create_publisher<msg::Odometry>("pose_gt", {.pool_size = 2});
    create_timer(std::chrono::milliseconds(50), [this] {
      auto loan = pose_.loan();
      if (!loan) return;
      msg::Odometry& o = **loan;
      o = msg::Odometry{};
      o.header.stamp_ns = clock().now_ns();
      const double t = 1e-9 * static_cast<double>(o.header.stamp_ns);
      const double b = config_.blink_period_s;
      const bool there = config_.skip_period_s <= 0 && (b <= 0 || std::fmod(t + 0.1, b) < 0.5 * b);
      o.T_world_body.position = {2.05, there ? 0.05 : 1.5, 0.05};
      o.T_world_body.orientation = {.w = 0, .x = 0, .y = 0, .z = 1};  // yaw π
      o.tracking_quality = 1;
      (void)pose_.publish(std::move(*loan));
    });
    if (config_.skip_period_s > 0) {
      // the robot never gets there: its low-level planner skips the viewpoint, again and again
      skipped_ = create_publisher<msg::Odometry>("skipped_goal", {.pool_size = 2});
      create_timer(std::chrono::nanoseconds(std::llround(config_.skip_period_s * 1e9)), [this] {
        auto loan = skipped_.loan();
        if (!loan) return;
        msg::Odometry& o = **loan;
        o = msg::Odometry{};
        o.header.stamp_ns = clock().now_ns();
        o.T_world_body.position = {2.05, 0.05, 0.05};
        o.T_world_body.orientation = {.w = 0, .x = 0, .y = 0, .z = 1};  // yaw π
        (void)skipped_.publish(std::move(*loan));
      });
    }
    create_timer(std::chrono::nanoseconds(std::llround(config_.map_period_s * 1e9)), [this] {
      auto loan = map_.loan();
      if (!loan) return;
      (*loan)->header.stamp_ns = clock().now_ns();
      (*loan)->map = scene_.snapshot();
      (void)map_.publish(std::move(*loan));
    });
    return {};
  }

  Config config_;
  ise::test::VoxelScene scene_;
  Publisher<msg::MapUpdate> map_;
  Publisher<msg::Odometry> pose_;
  Publisher<msg::Odometry> skipped_;
};
SCANCREW_REGISTER_COMPONENT(RoomFeeder, "test_room_feeder")

// Keeps the stamps and |C_ins| of the ISE sets.
class IseLog final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps |C_ins| per ISE set";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  IseLog(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  std::vector<std::pair<double, uint32_t>> inspectable;  // (t_s, |C_ins|)

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::IseSet>("ises", {.depth = 8}, [this](Sample<msg::IseSet>&& s) {
      inspectable.emplace_back(1e-9 * static_cast<double>(s->header.stamp_ns), s->inspectable);
    });
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(IseLog, "test_ise_log")

struct GiveUp {
  double first_update_s = -1;  // the first ISE set
  double given_up_s = -1;      // the first with one inspectable ISE fewer (-1: never)
};

// The room's parameters (scenes.hpp pipeline_config) on the component.
GiveUp run_room(double map_period_s, double visit_period_s, double blink_period_s = 0,
                double skip_period_s = 0) {
  const std::string text =
      R"(clock: sim
executor: {type: step}
run: {duration_s: 8.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: multirotor, start: [2.05, 0.05, 0.05, 180]}
remap: {pose: pose_gt}
components:
  - {name: feed, type: test_room_feeder, params: {map_period_s: )" +
      std::to_string(map_period_s) + ", blink_period_s: " + std::to_string(blink_period_s) +
      ", skip_period_s: " + std::to_string(skip_period_s) + R"(}}
  - name: ise
    type: ise_extractor
    params: {multirotor_delta_pose_m: 2.0,
             multirotor_min_range_m: 0.3, multirotor_max_range_m: 5.0,
             multirotor_clearance_m: 0.3, d_v_m: 2.0, d_v_max_m: 5.0, gain_rows: 5,
             gain_cols: 7, completion_updates: 2, give_up_visits: 3, visit_period_s: )" +
      std::to_string(visit_period_s) + R"(}
  - {name: log, type: test_ise_log}
)";
  GiveUp out;
  auto launch = Launch::from_string(text, "ise_extractor_test.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  if (!launch) return out;
  (*launch)->run();
  const auto* log = (*launch)->find_component<IseLog>();
  EXPECT_NE(log, nullptr);
  if (log == nullptr || log->inspectable.empty()) return out;
  out.first_update_s = log->inspectable.front().first;
  const uint32_t at_first = log->inspectable.front().second;
  EXPECT_EQ(at_first, 2u);  // both ISEs of the room
  for (const auto& [t, n] : log->inspectable)
    if (n < at_first) {
      out.given_up_s = t;
      break;
    }
  return out;
}

TEST(IseExtractor, GivesUpAfterTheSameTimeStandingWhateverTheMapRate) {
  // 3 visits 1 s apart: given up at the third counting update, 2 s after the first, and in
  // C_rem from the next update on
  for (const double map_period_s : {1.0, 0.5, 0.25}) {
    const GiveUp g = run_room(map_period_s, 1.0);
    ASSERT_GE(g.given_up_s, 0) << map_period_s;
    const double standing_s = g.given_up_s - g.first_update_s;
    std::printf("[figures] map every %.2f s: given up %.2f s after the first update\n",
                map_period_s, standing_s);
    EXPECT_GE(standing_s, 2.0 + map_period_s - 1e-6) << map_period_s;
    EXPECT_LE(standing_s, 2.0 + 2 * map_period_s + 1e-6) << map_period_s;
  }
}

TEST(IseExtractor, EachArrivalAtTheViewpointCountsAVisit) {
  // the map every 0.25 s; the robot stands at the viewpoint for one update in two (at 0.5,
  // 1.0, 1.5 s): three arrivals, given up at the third, in C_rem at 1.75 s. Counting on a
  // fixed 1 s clock instead counted at 0.5, 1.5 and 2.5 s only
  const GiveUp g = run_room(0.25, 1.0, 0.5);
  ASSERT_GE(g.given_up_s, 0);
  std::printf("[figures] arriving every 0.5 s: given up at %.2f s\n", g.given_up_s);
  EXPECT_NEAR(g.given_up_s, 1.75, 1e-6);
}

TEST(IseExtractor, EachSkippedViewpointCountsAVisit) {
  // the robot stands 1.45 m aside all along; its low-level planner skips the viewpoint at
  // 1, 2 and 3 s (no path to it): given up at the update after the third skip, in C_rem
  // from the next. Never skipped, it stays
  const GiveUp skipped = run_room(0.25, 1.0, 0.0, 1.0);
  ASSERT_GE(skipped.given_up_s, 0);
  std::printf("[figures] skipped every 1 s: given up at %.2f s\n", skipped.given_up_s);
  EXPECT_GT(skipped.given_up_s, 3.0);
  EXPECT_LE(skipped.given_up_s, 3.5 + 1e-6);
  const GiveUp aside = run_room(0.25, 1.0, 0.0, 10.0);  // the first skip after the 8 s run
  EXPECT_LT(aside.given_up_s, 0) << "a robot aside of the viewpoint, never skipping it";
}

TEST(IseExtractor, AZeroVisitPeriodCountsEveryUpdate) {
  // the rule as it was: the third update gives up, whatever the time between them
  const GiveUp g = run_room(0.25, 0.0);
  ASSERT_GE(g.given_up_s, 0);
  EXPECT_NEAR(g.given_up_s - g.first_update_s, 3 * 0.25, 1e-6);
}

TEST(IseExtractor, RefusesANegativeVisitPeriod) {
  const std::string text = R"(clock: sim
executor: {type: step}
run: {duration_s: 1.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: multirotor, start: [0, 0, 1, 0]}
remap: {pose: pose_gt}
components:
  - {name: ise, type: ise_extractor, params: {give_up_visits: 3, visit_period_s: -1}}
)";
  auto launch = Launch::from_string(text, "ise_extractor_bad.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("visit_period_s"), std::string::npos)
      << launch.error().front();
}

}  // namespace
}  // namespace scancrew::ise_extractor
