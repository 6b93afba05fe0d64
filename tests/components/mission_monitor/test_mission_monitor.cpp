// The mission_monitor component on sim time with the step executor, fed by a scripted
// component (poses, robot states, ISE sets at chosen times): path lengths and samples,
// replanning requests, completion when every ISE source reports complete (the launch stops
// there through its stop condition), a stall when every robot idles, bad configuration;
// maps: none (per-robot ISEs, no maps) and lost robots (kLost states, as the dds_bridge
// publishes them) left out of the completion and stall tests until they come back.

#include <gtest/gtest.h>

#include <cmath>

#include "components/mission_monitor/mission_monitor.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/map_update.hpp"

namespace scancrew::mission_monitor {
namespace {

struct Script {
  // (time, robot index, x) poses: the robot moves along x
  std::vector<std::tuple<double, size_t, double>> poses;
  std::vector<std::tuple<double, size_t, msg::RobotState::Mode>> states;
  // (time, robot index, inspectable, complete)
  std::vector<std::tuple<double, size_t, uint32_t, bool>> ises;
  // each robot's map says at 0.1 s that it integrated a depth image of it (false: never)
  bool depth_integrated = true;
};
Script g_script;  // NOLINT: set by each test before its launch runs

class Feeder final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: scripted poses, states and ISEs";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Feeder(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

 private:
  Result<void, std::string> on_configure() override {
    for (const TeamMember& m : team()) {
      poses_.push_back(create_publisher<msg::Odometry>("/" + m.ns + "/pose_gt"));
      states_.push_back(create_publisher<msg::RobotState>("/" + m.ns + "/robot_state"));
      ises_.push_back(create_publisher<msg::IseSet>("/" + m.ns + "/ises"));
      maps_.push_back(create_publisher<msg::MapUpdate>("/" + m.ns + "/map"));
      ids_.push_back(m.id);
    }
    create_timer(std::chrono::milliseconds(100), [this] { tick(); });
    return {};
  }
  void tick() {
    const double t = static_cast<double>(clock().now_ns()) * 1e-9;
    const auto due = [&](double at) { return at <= t + 1e-9 && at > last_ + 1e-9; };
    if (due(0.1) && g_script.depth_integrated)
      for (size_t i = 0; i < maps_.size(); ++i)
        if (auto loan = maps_[i].loan()) {
          (*loan)->robots_integrated = {ids_[i]};
          (*loan)->frames_integrated = 1;
          (void)maps_[i].publish(std::move(*loan));
        }
    for (const auto& [at, robot, x] : g_script.poses)
      if (due(at))
        if (auto loan = poses_[robot].loan()) {
          **loan = msg::Odometry{};
          (*loan)->T_world_body.position.x = x;
          (*loan)->T_world_body.orientation.w = 1;
          (*loan)->tracking_quality = 1;
          (void)poses_[robot].publish(std::move(*loan));
        }
    for (const auto& [at, robot, mode] : g_script.states)
      if (due(at))
        if (auto loan = states_[robot].loan()) {
          **loan = msg::RobotState{};
          (*loan)->mode = mode;
          (void)states_[robot].publish(std::move(*loan));
        }
    for (const auto& [at, robot, inspectable, complete] : g_script.ises)
      if (due(at))
        if (auto loan = ises_[robot].loan()) {
          **loan = msg::IseSet{};
          (*loan)->inspectable = inspectable;
          (*loan)->complete = complete ? 1 : 0;
          (void)ises_[robot].publish(std::move(*loan));
        }
    last_ = t;
  }
  std::vector<Publisher<msg::Odometry>> poses_;
  std::vector<Publisher<msg::RobotState>> states_;
  std::vector<Publisher<msg::IseSet>> ises_;
  std::vector<Publisher<msg::MapUpdate>> maps_;
  std::vector<uint32_t> ids_;
  double last_ = -1;
};
SCANCREW_REGISTER_COMPONENT(Feeder, "test_mission_feeder")

constexpr const char* kTwoRobots = "  - {id: 1, namespace: r1}\n  - {id: 2, namespace: r2}\n";
constexpr const char* kThreeRobots =
    "  - {id: 1, namespace: r1}\n  - {id: 2, namespace: r2}\n  - {id: 3, namespace: r3}\n";

std::string launch_text(const std::string& monitor_params, double duration_s = 60,
                        const std::string& robots = kTwoRobots) {
  // compute free: the times below are exact
  return "clock: sim\nexecutor: {type: step}\nrun: {duration_s: " + std::to_string(duration_s) +
         ", sim_step_s: 0.1, compute_time: free}\n"
         "robots:\n" +
         robots +
         "components:\n"
         "  - {name: feeder, type: test_mission_feeder, per_robot: false}\n"
         "  - {name: monitor, type: mission_monitor, per_robot: false, params: {" +
         monitor_params + "}}\n";
}

std::unique_ptr<Launch> make_launch(const std::string& text) {
  auto launch = Launch::from_string(text, "test_mission.yaml");
  EXPECT_TRUE(launch.has_value()) << (launch ? "" : launch.error().front());
  return launch ? std::move(launch).value() : nullptr;
}

using Mode = msg::RobotState::Mode;

TEST(MissionMonitor, IntegratesPathsSamplesThemAndCountsReplanningRequests) {
  g_script = {};
  for (int k = 0; k <= 10; ++k) g_script.poses.emplace_back(0.1 * (k + 1), 0, 0.5 * k);  // 5 m
  g_script.poses.emplace_back(0.1, 1, 2.0);  // robot 2 stands still
  g_script.states = {{0.2, 0, Mode::kPlanning}, {0.4, 0, Mode::kMoving}, {0.6, 0, Mode::kPlanning},
                     {0.7, 0, Mode::kPlanning}, {0.8, 0, Mode::kMoving}, {0.3, 1, Mode::kPlanning}};
  auto launch = make_launch(launch_text("path_period_s: 0.5, stall_timeout_s: 0", 3.0));
  ASSERT_TRUE(launch);
  launch->run();
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  const auto robots = monitor->robots();
  ASSERT_EQ(robots.size(), 2u);
  EXPECT_NEAR(robots[0].path_length_m, 5.0, 1e-9);
  EXPECT_NEAR(robots[1].path_length_m, 0.0, 1e-12);
  EXPECT_EQ(robots[0].planning_requests, 2u);  // two entries into kPlanning, not three states
  EXPECT_EQ(robots[1].planning_requests, 1u);
  EXPECT_EQ(robots[0].mode, Mode::kMoving);
  EXPECT_LT(robots[0].coverage, 0);  // no scene: no coverage estimate
  EXPECT_FALSE(monitor->finished());
  // path samples every 0.5 s for each robot with a pose; the last one of robot 1 at x = 5
  const auto paths = monitor->paths();
  size_t r1 = 0;
  double last_x = -1;
  for (const auto& p : paths)
    if (p.robot_id == 1) {
      ++r1;
      last_x = p.x_m;
    }
  EXPECT_GE(r1, 5u);
  EXPECT_NEAR(last_x, 5.0, 1e-9);
}

TEST(MissionMonitor, CompletesWhenEveryIseSourceIsCompleteAndStopsTheLaunchThere) {
  g_script = {};
  g_script.ises = {{1.0, 0, 40, false},
                   {1.0, 1, 40, false},
                   {5.0, 0, 0, true},
                   {8.0, 1, 3, false},
                   {12.0, 1, 0, true}};
  auto launch = make_launch(launch_text("stall_timeout_s: 0"));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  const double ran = launch->run();
  EXPECT_TRUE(monitor->finished());
  EXPECT_EQ(monitor->stop_reason(), "complete");
  ASSERT_TRUE(monitor->completion_time_s().has_value());
  EXPECT_NEAR(*monitor->completion_time_s(), 12.0, 0.11);
  EXPECT_LT(ran, 12.5);  // stopped at completion, not at the 60 s budget
  const auto robots = monitor->robots();
  EXPECT_TRUE(robots[0].complete && robots[1].complete);
  EXPECT_EQ(robots[1].ises_left, 0u);
}

// A robot whose depth never reached a map saw nothing: its source's empty C_ins is no
// completion (a mapper reading a topic nobody publishes once "completed" at 0.5 s).
TEST(MissionMonitor, ASourceCompleteBeforeItsRobotsDepthIsIntegratedIsNoCompletion) {
  g_script = {};
  g_script.depth_integrated = false;
  g_script.ises = {{1.0, 0, 0, true}, {1.0, 1, 0, true}};
  auto launch = make_launch(launch_text("stall_timeout_s: 0", 5.0));
  ASSERT_TRUE(launch);
  auto* monitor = launch->find_component<MissionMonitor>();
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  EXPECT_NEAR(launch->run(), 5.0, 1e-6);
  EXPECT_FALSE(monitor->finished());
  EXPECT_EQ(monitor->robots_without_depth(), (std::vector<std::string>{"r1", "r2"}));
}

// Every interval of mission time goes to one activity: the breakdowns sum to the time run.
TEST(MissionMonitor, TimeBreakdownSumsToTheMissionTime) {
  g_script = {};
  g_script.states = {{0.2, 0, Mode::kPlanning},
                     {1.0, 0, Mode::kMoving},
                     {3.0, 0, Mode::kIdle},
                     {0.2, 1, Mode::kIdle}};
  g_script.ises = {{0.5, 0, 5, false}, {0.5, 1, 0, true}};
  auto launch = make_launch(launch_text("path_period_s: 0.5, stall_timeout_s: 0", 7.3));
  ASSERT_TRUE(launch);
  auto* monitor = launch->find_component<MissionMonitor>();
  const double ran = launch->run();
  monitor->close_time_breakdown();
  for (const auto& r : monitor->robots()) EXPECT_NEAR(r.time.total(), ran, 1e-9) << r.ns;
  const auto robots = monitor->robots();
  using report::Activity;
  // robot 1: waiting (no state, planning, moving without motion) until 3 s, then idle with
  // ISEs open; robot 2: idle after its source's completion from 0.5 s on
  EXPECT_NEAR(robots[0].time.of(Activity::kWaiting), 3.0, 0.51);
  EXPECT_NEAR(robots[0].time.of(Activity::kIdleOpen), ran - 3.0, 0.51);
  EXPECT_NEAR(robots[1].time.of(Activity::kIdleDone), ran - 0.5, 0.51);
  EXPECT_EQ(robots[0].time.of(Activity::kDriving), 0.0);
}

TEST(MissionMonitor, OneIncompleteSourceKeepsTheMissionGoing) {
  g_script = {};
  g_script.ises = {{1.0, 0, 0, true}, {1.0, 1, 7, false}};
  auto launch = make_launch(launch_text("stall_timeout_s: 0", 10.0));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  EXPECT_NEAR(launch->run(), 10.0, 1e-6);
  EXPECT_FALSE(monitor->finished());
  EXPECT_FALSE(monitor->completion_time_s().has_value());
}

TEST(MissionMonitor, EveryRobotIdleForTheStallTimeoutStopsAsStalled) {
  g_script = {};
  g_script.ises = {{1.0, 0, 9, false}, {1.0, 1, 9, false}};
  g_script.states = {{1.0, 0, Mode::kIdle}, {2.0, 1, Mode::kMoving}, {4.0, 1, Mode::kIdle}};
  auto launch = make_launch(launch_text("stall_timeout_s: 10"));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  const double ran = launch->run();
  EXPECT_EQ(monitor->stop_reason(), "stalled");
  EXPECT_FALSE(monitor->completion_time_s().has_value());
  EXPECT_NEAR(ran, 14.0, 0.6);  // robot 2 idle since 4 s, 10 s timeout (path ticks check it)
}

TEST(MissionMonitor, BadConfigurationIsRefusedNamingTheCause) {
  auto bad_scene = Launch::from_string(launch_text("scene: /nonexistent/scene.yaml"), "m.yaml");
  ASSERT_FALSE(bad_scene.has_value());
  bool named = false;
  for (const auto& e : bad_scene.error())
    named = named || e.find("nonexistent") != std::string::npos;
  EXPECT_TRUE(named);
  auto bad_maps = Launch::from_string(launch_text("maps: everywhere"), "m.yaml");
  ASSERT_FALSE(bad_maps.has_value());
  EXPECT_NE(bad_maps.error().front().find("maps"), std::string::npos);
  const std::string no_robots =
      "clock: sim\nexecutor: {type: step}\ncomponents:\n"
      "  - {name: monitor, type: mission_monitor, per_robot: false}\n";
  EXPECT_FALSE(Launch::from_string(no_robots, "m.yaml").has_value());
}

// maps: none (a simulator process that cannot see the robots' maps): one ISE source per
// robot, no coverage; robot 3 is lost (the dds_bridge's kLost on /r3/robot_state) and the
// mission completes when robots 1 and 2 do.
TEST(MissionMonitor, ALostRobotIsLeftOutOfTheCompletionTest) {
  g_script = {};
  g_script.ises = {{1.0, 0, 40, false},
                   {1.0, 1, 40, false},
                   {1.0, 2, 40, false},
                   {5.0, 0, 0, true},
                   {6.0, 1, 0, true}};
  g_script.states = {{0.5, 2, Mode::kMoving}, {2.0, 2, Mode::kLost}};
  auto launch = make_launch(launch_text("maps: none, stall_timeout_s: 0", 30, kThreeRobots));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  EXPECT_EQ(monitor->config().maps, MapSources::kNone);
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  const double ran = launch->run();
  EXPECT_EQ(monitor->stop_reason(), "complete");
  ASSERT_TRUE(monitor->completion_time_s().has_value());
  EXPECT_NEAR(*monitor->completion_time_s(), 6.0, 0.11);
  EXPECT_LT(ran, 6.5);
  const auto robots = monitor->robots();
  ASSERT_EQ(robots.size(), 3u);
  EXPECT_EQ(robots[2].mode, Mode::kLost);
  EXPECT_FALSE(robots[2].complete);
  EXPECT_EQ(robots[2].ises_left, 40u);  // per-robot sources: robot 3's own, not the others'
  for (const auto& r : robots) EXPECT_LT(r.coverage, 0);  // maps: none: not measured
  EXPECT_TRUE(monitor->coverage().empty());
  EXPECT_NE(monitor->status_line().find("r3 lost"), std::string::npos) << monitor->status_line();
}

TEST(MissionMonitor, WithoutTheLostStateEveryRobotMustComplete) {
  g_script = {};
  g_script.ises = {{1.0, 0, 40, false}, {1.0, 1, 40, false}, {1.0, 2, 40, false},
                   {5.0, 0, 0, true},   {6.0, 1, 0, true},   {9.0, 2, 0, true}};
  g_script.states = {{0.5, 2, Mode::kMoving}};
  auto launch = make_launch(launch_text("maps: none, stall_timeout_s: 0", 30, kThreeRobots));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  const double ran = launch->run();
  EXPECT_EQ(monitor->stop_reason(), "complete");
  ASSERT_TRUE(monitor->completion_time_s().has_value());
  EXPECT_NEAR(*monitor->completion_time_s(), 9.0, 0.11);  // not at 6 s: robot 3 was not done
  EXPECT_GT(ran, 8.9);
  EXPECT_LT(ran, 9.5);
}

TEST(MissionMonitor, ARobotThatComesBackCountsAgain) {
  g_script = {};
  g_script.ises = {{1.0, 0, 40, false}, {1.0, 1, 40, false}, {1.0, 2, 40, false},
                   {5.0, 0, 0, true},   {6.0, 1, 0, true},   {9.0, 2, 0, true}};
  // lost at 2 s, back (moving) at 4 s: before robots 1 and 2 complete
  g_script.states = {{0.5, 2, Mode::kMoving}, {2.0, 2, Mode::kLost}, {4.0, 2, Mode::kMoving}};
  auto launch = make_launch(launch_text("maps: none, stall_timeout_s: 0", 30, kThreeRobots));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  launch->run();
  EXPECT_EQ(monitor->stop_reason(), "complete");
  ASSERT_TRUE(monitor->completion_time_s().has_value());
  EXPECT_NEAR(*monitor->completion_time_s(), 9.0, 0.11);
  EXPECT_EQ(monitor->robots()[2].mode, Mode::kMoving);
}

TEST(MissionMonitor, LosingTheLastIncompleteRobotCompletesTheMissionAtOnce) {
  g_script = {};
  g_script.ises = {{1.0, 0, 0, true}, {1.0, 1, 0, true}, {1.0, 2, 12, false}};
  g_script.states = {{0.5, 2, Mode::kMoving}, {7.0, 2, Mode::kLost}};
  auto launch = make_launch(
      launch_text("maps: none, stall_timeout_s: 0, path_period_s: 5", 30, kThreeRobots));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  launch->run();
  EXPECT_EQ(monitor->stop_reason(), "complete");
  ASSERT_TRUE(monitor->completion_time_s().has_value());
  // decided on the state itself, not at the next path tick (10 s)
  EXPECT_NEAR(*monitor->completion_time_s(), 7.0, 0.11);
}

TEST(MissionMonitor, EveryRobotLostIsNotCompleteButStalls) {
  g_script = {};
  g_script.ises = {{1.0, 0, 0, true}, {1.0, 1, 5, false}, {1.0, 2, 5, false}};
  g_script.states = {{2.0, 0, Mode::kLost}, {3.0, 1, Mode::kLost}, {4.0, 2, Mode::kLost}};
  {
    auto launch = make_launch(launch_text("maps: none, stall_timeout_s: 0", 20, kThreeRobots));
    ASSERT_TRUE(launch);
    const auto* monitor = launch->find_component<MissionMonitor>();
    ASSERT_NE(monitor, nullptr);
    launch->set_stop_condition([monitor] { return monitor->finished(); });
    EXPECT_NEAR(launch->run(), 20.0, 1e-6);
    EXPECT_FALSE(monitor->finished());
    EXPECT_EQ(monitor->stop_reason(), "");
    EXPECT_FALSE(monitor->completion_time_s().has_value());
  }
  auto launch = make_launch(launch_text("maps: none, stall_timeout_s: 10", 60, kThreeRobots));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  const double ran = launch->run();
  EXPECT_EQ(monitor->stop_reason(), "stalled");
  EXPECT_FALSE(monitor->completion_time_s().has_value());
  EXPECT_NEAR(ran, 14.0, 0.6);  // the last robot lost at 4 s, 10 s timeout
}

TEST(MissionMonitor, ALostRobotDoesNotKeepTheOthersFromStalling) {
  g_script = {};
  g_script.ises = {{1.0, 0, 9, false}, {1.0, 1, 9, false}, {1.0, 2, 9, false}};
  g_script.states = {{1.0, 0, Mode::kIdle}, {1.0, 1, Mode::kIdle}, {1.0, 2, Mode::kMoving}};
  {
    // robot 3 moving: no stall
    auto launch = make_launch(launch_text("maps: none, stall_timeout_s: 10", 30, kThreeRobots));
    ASSERT_TRUE(launch);
    const auto* monitor = launch->find_component<MissionMonitor>();
    ASSERT_NE(monitor, nullptr);
    launch->set_stop_condition([monitor] { return monitor->finished(); });
    EXPECT_NEAR(launch->run(), 30.0, 1e-6);
    EXPECT_FALSE(monitor->finished());
  }
  g_script.states.emplace_back(3.0, 2, Mode::kLost);
  auto launch = make_launch(launch_text("maps: none, stall_timeout_s: 10", 30, kThreeRobots));
  ASSERT_TRUE(launch);
  const auto* monitor = launch->find_component<MissionMonitor>();
  ASSERT_NE(monitor, nullptr);
  launch->set_stop_condition([monitor] { return monitor->finished(); });
  const double ran = launch->run();
  EXPECT_EQ(monitor->stop_reason(), "stalled");
  EXPECT_NEAR(ran, 11.0, 0.6);  // robots 1 and 2 idle since 1 s
}

}  // namespace
}  // namespace scancrew::mission_monitor
