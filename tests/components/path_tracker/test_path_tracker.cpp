// The path tracker on the sim backend (test arena, sim time, bounded runs): a ground
// robot and a multirotor follow a path through a sequence of waypoints and stop at the
// last within tolerance; a stop maneuver zeroes the command at once and the robot stays
// put until resumed; a step-aside maneuver takes it to the aside pose, and it finishes
// the path after the resume; stale plans, empty paths and NaN poses stop it safely.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "components/path_tracker/path_tracker.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::path_tracker {
namespace {

// Keeps the ground-truth poses, the commands and the tracker states.
class TrackerLog final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps pose_gt, cmd_vel, tracker_state";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  TrackerLog(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  std::vector<msg::Odometry> poses;
  std::vector<msg::VelocityCommand> commands;
  std::vector<msg::RobotState> states;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::Odometry>("pose_gt", {.depth = 8},
                                       [this](Sample<msg::Odometry>&& s) { poses.push_back(*s); });
    create_subscription<msg::VelocityCommand>(
        "cmd_vel", {.depth = 8},
        [this](Sample<msg::VelocityCommand>&& s) { commands.push_back(*s); });
    create_subscription<msg::RobotState>(
        "tracker_state", {.depth = 8},
        [this](Sample<msg::RobotState>&& s) { states.push_back(*s); });
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(TrackerLog, "test_tracker_log")

// Sends what the traffic policy and a faulty planner or estimator would:
//   maneuvers  [t_s, kind (0 resume, 1 stop, 2 step aside), x, y, z, yaw_deg] sextuples
//   empty_path_at_s / empty_plan_id: an empty LocalPath at that time
//   nan_odom: a NaN pose on `odom` every 0.2 s
class TestInjector final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: maneuvers, empty paths, NaN poses";
  struct Config {
    std::vector<double> maneuvers;
    double empty_path_at_s = -1;
    uint64_t empty_plan_id = 0;
    bool nan_odom = false;
    bool lost_odom = false;  // finite poses with tracking quality 0 (the odometry lost track)
  };
  static Config read_config(ParamReader& p) {
    Config c;
    p.optional_list("maneuvers", c.maneuvers);
    p.optional("empty_path_at_s", c.empty_path_at_s);
    p.optional("empty_plan_id", c.empty_plan_id);
    p.optional("nan_odom", c.nan_odom);
    p.optional("lost_odom", c.lost_odom);
    return c;
  }
  TestInjector(ComponentContext c, Config config)
      : Component(std::move(c)), config_(std::move(config)) {}

 private:
  Result<void, std::string> on_configure() override {
    maneuver_ = create_publisher<msg::Maneuver>("maneuver");
    path_ = create_publisher<msg::LocalPath>("local_path");
    odom_ = create_publisher<msg::Odometry>("odom");
    create_timer(std::chrono::milliseconds(50), [this] { tick(); });
    return {};
  }
  void tick() {
    const double t = 1e-9 * static_cast<double>(clock().now_ns());
    for (; next_ + 5 < config_.maneuvers.size() && config_.maneuvers[next_] <= t + 1e-9;
         next_ += 6) {
      auto loan = maneuver_.loan();
      ASSERT_TRUE(loan);
      msg::Maneuver& m = **loan;
      m.kind = static_cast<msg::Maneuver::Kind>(static_cast<int>(config_.maneuvers[next_ + 1]));
      m.aside = {{config_.maneuvers[next_ + 2], config_.maneuvers[next_ + 3],
                  config_.maneuvers[next_ + 4]},
                 config_.maneuvers[next_ + 5] * M_PI / 180};
      (void)maneuver_.publish(std::move(*loan));
    }
    if (config_.empty_path_at_s >= 0 && t + 1e-9 >= config_.empty_path_at_s) {
      config_.empty_path_at_s = -1;
      auto loan = path_.loan();
      ASSERT_TRUE(loan);
      (**loan).plan_id = config_.empty_plan_id;
      (**loan).waypoints.clear();
      (void)path_.publish(std::move(*loan));
    }
    if (config_.nan_odom && std::llround(t * 20) % 4 == 0) {
      auto loan = odom_.loan();
      ASSERT_TRUE(loan);
      (**loan).T_world_body.position.x = std::numeric_limits<double>::quiet_NaN();
      (**loan).tracking_quality = 1.0;
      (void)odom_.publish(std::move(*loan));
    }
    if (config_.lost_odom && std::llround(t * 20) % 4 == 0) {
      auto loan = odom_.loan();
      ASSERT_TRUE(loan);
      (**loan).header.stamp_ns = clock().now_ns();
      (**loan).T_world_body.position = {-3, -2, 0};
      (**loan).tracking_quality = 0.0;
      (void)odom_.publish(std::move(*loan));
    }
  }
  Config config_;
  Publisher<msg::Maneuver> maneuver_;
  Publisher<msg::LocalPath> path_;
  Publisher<msg::Odometry> odom_;
  size_t next_ = 0;
};
SCANCREW_REGISTER_COMPONENT(TestInjector, "test_tracker_injector")

struct Waypoint4 {
  double x, y, z, yaw_deg;
};

std::string list(const std::vector<Waypoint4>& w) {
  std::string s = "[";
  for (const Waypoint4& p : w)
    s += std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) + ", " +
         std::to_string(p.yaw_deg) + (&p == &w.back() ? "" : ", ");
  return s + "]";
}

std::string launch_text(const std::string& kind, const Waypoint4& start, double duration_s,
                        const std::string& player, const std::string& tracker,
                        const std::string& injector, const std::string& pose = "pose_gt") {
  return R"(
clock: sim
executor: {type: step}
run: {duration_s: )" +
         std::to_string(duration_s) + R"(, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: )" +
         kind + ", start: [" + std::to_string(start.x) + ", " + std::to_string(start.y) + ", " +
         std::to_string(start.z) + ", " + std::to_string(start.yaw_deg) +
         R"(]}
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params: {scene: )" SCANCREW_SOURCE_DIR
         R"(/launch_cfg/scenes/test_arena.yaml, publish_stereo: false, publish_depth: false}
  - {name: player, type: path_player, params: )" +
         player + R"(}
  - {name: tracker, type: path_tracker, remap: {pose: )" +
         pose + "}, params: " + tracker + R"(}
  - {name: log, type: test_tracker_log}
  - {name: inject, type: test_tracker_injector, params: )" +
         injector + R"(}
)";
}

struct TrackerRun {
  std::unique_ptr<Launch> launch;
  PathTracker* tracker = nullptr;
  TrackerLog* log = nullptr;
};

TrackerRun run(const std::string& text) {
  TrackerRun r;
  auto launch = Launch::from_string(text, "tracker_test.yaml");
  EXPECT_TRUE(launch) << (launch ? "" : launch.error().front());
  if (!launch) return r;
  r.launch = std::move(launch).value();
  r.launch->run();
  r.tracker = r.launch->find_component<PathTracker>();
  r.log = r.launch->find_component<TrackerLog>();
  return r;
}

double t_s(const msg::Header& h) {
  return 1e-9 * static_cast<double>(h.stamp_ns);
}
double distance(const msg::Odometry& o, const Waypoint4& w, bool planar) {
  const auto& p = o.T_world_body.position;
  return std::sqrt((p.x - w.x) * (p.x - w.x) + (p.y - w.y) * (p.y - w.y) +
                   (planar ? 0.0 : (p.z - w.z) * (p.z - w.z)));
}
double yaw_of(const msg::Odometry& o) {
  const auto& q = o.T_world_body.orientation;
  return std::atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}
double yaw_error_deg(const msg::Odometry& o, const Waypoint4& w) {
  return std::abs(std::remainder(w.yaw_deg * M_PI / 180 - yaw_of(o), 2 * M_PI)) * 180 / M_PI;
}

// Follows `path` from `start`; checks every waypoint is passed near, the limits, the
// progress, and the goal. Prints the figures (docs/path_tracker.md).
void expect_follows(const std::string& kind, const Waypoint4& start,
                    const std::vector<Waypoint4>& path, double max_speed_mps,
                    double max_duration_s) {
  const bool ground = kind == "ground";
  TrackerRun r =
      run(launch_text(kind, start, max_duration_s, "{waypoints: " + list(path) + "}", "{}", "{}"));
  ASSERT_NE(r.tracker, nullptr);
  ASSERT_NE(r.log, nullptr);
  ASSERT_FALSE(r.log->poses.empty());
  EXPECT_EQ(r.tracker->plans_done(), 1u) << kind;
  EXPECT_EQ(r.tracker->mode(), msg::RobotState::Mode::kDone) << kind;
  EXPECT_LE(r.tracker->done_position_error_m(), 0.1) << kind;
  EXPECT_LE(r.tracker->done_yaw_error_rad(), 5 * M_PI / 180) << kind;
  // the robot at rest at the goal, as the simulator reports it
  const msg::Odometry& last = r.log->poses.back();
  const double final_error_m = distance(last, path.back(), ground);
  EXPECT_LT(final_error_m, 0.1) << kind;
  EXPECT_LT(yaw_error_deg(last, path.back()), 5.0) << kind;
  // every waypoint passed near (corners are cut by at most about the look-ahead's share)
  double worst_pass_m = 0;
  for (const Waypoint4& w : path) {
    double nearest = 1e9;
    for (const msg::Odometry& o : r.log->poses) nearest = std::min(nearest, distance(o, w, ground));
    EXPECT_LT(nearest, 0.35) << kind << " waypoint " << w.x << ", " << w.y;
    worst_pass_m = std::max(worst_pass_m, nearest);
  }
  // limits: the commands
  for (const msg::VelocityCommand& c : r.log->commands) {
    const double v = std::sqrt(c.linear_mps.x * c.linear_mps.x + c.linear_mps.y * c.linear_mps.y +
                               c.linear_mps.z * c.linear_mps.z);
    EXPECT_LE(v, max_speed_mps + 1e-9) << kind;
    if (ground) {
      EXPECT_EQ(c.linear_mps.y, 0.0);
    }
  }
  // progress never goes back; done at the end
  uint32_t index = 0;
  for (const msg::RobotState& s : r.log->states) {
    EXPECT_GE(s.path_index, index) << kind;
    index = s.path_index;
  }
  ASSERT_FALSE(r.log->states.empty());
  EXPECT_EQ(r.log->states.back().path_index, path.size());
  EXPECT_EQ(r.log->states.back().steps_remaining, 0u);
  EXPECT_EQ(r.log->states.back().mode, msg::RobotState::Mode::kDone);
  double length_m = 0;
  for (size_t i = 1; i < path.size(); ++i)
    length_m += std::hypot(path[i].x - path[i - 1].x, path[i].y - path[i - 1].y,
                           ground ? 0.0 : path[i].z - path[i - 1].z);
  const double done_s = 1e-9 * static_cast<double>(r.tracker->done_stamp_ns());
  // at nominal speed most of the way: at most 40 % over length / speed, plus the turns
  EXPECT_LT(done_s, 1.4 * length_m / max_speed_mps + 6.0) << kind;
  std::printf(
      "[figures] %s: path %.2f m, done at %.1f s (length/speed %.1f s), travelled %.2f m, "
      "error at done %.3f m %.2f deg, final %.3f m %.2f deg, farthest waypoint pass %.2f m\n",
      kind.c_str(), length_m, done_s, length_m / max_speed_mps, r.tracker->travelled_m(),
      r.tracker->done_position_error_m(), r.tracker->done_yaw_error_rad() * 180 / M_PI,
      final_error_m, yaw_error_deg(last, path.back()), worst_pass_m);
}

TEST(PathTracker, AGroundRobotFollowsAPathThroughItsWaypointsToTheGoal) {
  // around the central obstacle (0.8 m wide at the origin), ending facing −x
  expect_follows("ground", {-2.5, -2.0, 0.0, 0.0},
                 {{-2.5, -2.0, 0, 0}, {2.0, -2.0, 0, 0}, {2.0, 2.0, 0, 90}, {-1.0, 2.0, 0, 180}},
                 0.5, 45.0);
}

TEST(PathTracker, AMultirotorFollowsAPathThroughItsWaypointsToTheGoal) {
  expect_follows(
      "multirotor", {-2.5, -2.0, 1.0, 0.0},
      {{-2.5, -2.0, 1.0, 0}, {2.0, -2.0, 1.5, 0}, {2.0, 2.0, 1.5, 90}, {-1.0, 2.0, 1.0, -90}}, 0.6,
      45.0);
}

// A back-off (the low-level planner's escape pose: 0.6 m behind, the same yaw) is driven
// backwards in a straight line; with ground_reverse_max_m 0 the robot turns round twice.
TEST(PathTracker, AGroundRobotBacksOffToAPoseJustBehindIt) {
  const Waypoint4 start{-2.0, -2.0, 0.0, 30.0};
  const Waypoint4 behind{-2.0 - 0.6 * std::cos(M_PI / 6), -2.0 - 0.6 * std::sin(M_PI / 6), 0, 30};
  const std::string player = "{waypoints: " + list({start, behind}) + "}";
  auto max_turn_deg = [&](const TrackerRun& r) {
    double turn = 0;
    for (const msg::Odometry& o : r.log->poses) turn = std::max(turn, yaw_error_deg(o, start));
    return turn;
  };
  TrackerRun back = run(launch_text("ground", start, 10.0, player, "{}", "{}"));
  ASSERT_NE(back.log, nullptr);
  ASSERT_FALSE(back.log->poses.empty());
  EXPECT_EQ(back.tracker->plans_done(), 1u);
  EXPECT_LT(distance(back.log->poses.back(), behind, true), 0.1);
  EXPECT_LT(max_turn_deg(back), 10.0);
  double v_min = 0;
  for (const msg::VelocityCommand& c : back.log->commands) v_min = std::min(v_min, c.linear_mps.x);
  EXPECT_LT(v_min, -0.1);
  TrackerRun round =
      run(launch_text("ground", start, 10.0, player, "{ground_reverse_max_m: 0.0}", "{}"));
  ASSERT_NE(round.log, nullptr);
  EXPECT_GT(max_turn_deg(round), 90.0);
}

// A goal behind and well to the side, with the robot's yaw: backing would turn the robot's
// back 70 degrees to it and its yaw away from the goal's; the robot must not flip between
// backing and turning forwards round (a 4-robot parking-lot run stood so for 300 s).
TEST(PathTracker, AGroundRobotReachesAGoalBehindAndAsideWithoutDithering) {
  const Waypoint4 start{-2.0, -2.0, 0.0, 0.0};
  const Waypoint4 goal{-2.0 + 0.8 * std::cos(110 * M_PI / 180),
                       -2.0 + 0.8 * std::sin(110 * M_PI / 180), 0, 0};
  TrackerRun r = run(
      launch_text("ground", start, 20.0, "{waypoints: " + list({start, goal}) + "}", "{}", "{}"));
  ASSERT_NE(r.tracker, nullptr);
  EXPECT_EQ(r.tracker->plans_done(), 1u);
  EXPECT_LT(distance(r.log->poses.back(), goal, true), 0.1);
  EXPECT_LT(1e-9 * static_cast<double>(r.tracker->done_stamp_ns()), 15.0);
}

// A back-off 0.2 m away, 45 degrees off straight back: the arc of at least 0.5 m the robot
// backs on cannot reach it; the robot backs past it, then drives forwards to it.
TEST(PathTracker, AGroundRobotReachesABackOffItsBackingArcPassesBy) {
  const Waypoint4 start{-2.0, -2.0, 0.0, 180.0};
  const Waypoint4 goal{-2.0 + 0.2 * std::cos(-M_PI / 4), -2.0 + 0.2 * std::sin(-M_PI / 4), 0,
                       180.0};
  TrackerRun r = run(
      launch_text("ground", start, 20.0, "{waypoints: " + list({start, goal}) + "}", "{}", "{}"));
  ASSERT_NE(r.tracker, nullptr);
  EXPECT_EQ(r.tracker->plans_done(), 1u);
  EXPECT_LT(distance(r.log->poses.back(), goal, true), 0.1);
  EXPECT_LT(yaw_error_deg(r.log->poses.back(), goal), 5.0);
  EXPECT_LT(1e-9 * static_cast<double>(r.tracker->done_stamp_ns()), 15.0);
}

// A path that doubles back at once: 0.26 m ahead and aside, then back past the start to the
// goal 0.87 m behind (a path the low-level planner sent in the parking lot, single robot,
// seed 5, shifted here). The look-ahead target 0.5 m along it lies on the second leg, 0.09
// m square to the side of the robot; the robot stood there for 1400 s, turned to the
// target's yaw and commanded to a standstill, while the projection stayed on the first leg.
TEST(PathTracker, AGroundRobotFollowsAPathThatDoublesBackBesideIt) {
  const Waypoint4 start{-2.018, -2.002, 0.0, 157.4};
  const std::vector<Waypoint4> path{
      {-2.000, -2.000, 0, 0}, {-1.918, -2.247, 0, 96.0}, {-2.660, -1.433, 0, 58.0}};
  TrackerRun r =
      run(launch_text("ground", start, 30.0, "{waypoints: " + list(path) + "}", "{}", "{}"));
  ASSERT_NE(r.tracker, nullptr);
  ASSERT_FALSE(r.log->poses.empty());
  EXPECT_EQ(r.tracker->plans_done(), 1u);
  EXPECT_LT(distance(r.log->poses.back(), path.back(), true), 0.1);
  EXPECT_LT(yaw_error_deg(r.log->poses.back(), path.back()), 5.0);
  EXPECT_LT(1e-9 * static_cast<double>(r.tracker->done_stamp_ns()), 20.0);
}

// A straight run along y = −2; a stop at 5 s, a resume at 10 s.
TEST(PathTracker, AStopManeuverZeroesTheCommandAtOnceAndHoldsUntilResumed) {
  for (const std::string kind : {"ground", "multirotor"}) {
    const std::vector<Waypoint4> path = {{-3, -2, 1, 0}, {3, -2, 1, 0}};
    TrackerRun r = run(launch_text(kind, {-3, -2, 1, 0}, 25.0, "{waypoints: " + list(path) + "}",
                                   "{}", "{maneuvers: [5.0, 1, 0, 0, 0, 0, 10.0, 0, 0, 0, 0, 0]}"));
    ASSERT_NE(r.tracker, nullptr);
    // the first command stamped at or after the stop is zero, and every one until the resume
    // (a tick in the same step as the order may come just before it, at the same stamp)
    const msg::VelocityCommand* at_order = nullptr;
    for (const msg::VelocityCommand& c : r.log->commands)
      if (std::abs(t_s(c.header) - 5.0) < 1e-6) at_order = &c;
    ASSERT_NE(at_order, nullptr);
    EXPECT_EQ(at_order->linear_mps.x, 0.0) << kind;  // sent with the order, not at the next tick
    bool seen = false;
    for (const msg::VelocityCommand& c : r.log->commands) {
      const double t = t_s(c.header);
      if (t < 5.0 + 1e-6) continue;
      if (t >= 10.0 - 1e-6) break;
      seen = true;
      EXPECT_EQ(c.linear_mps.x, 0.0) << kind;
      EXPECT_EQ(c.linear_mps.y, 0.0) << kind;
      EXPECT_EQ(c.linear_mps.z, 0.0) << kind;
      EXPECT_EQ(c.yaw_rate_radps, 0.0) << kind;
    }
    EXPECT_TRUE(seen);
    // moving at the stop; then within a few cm, and still
    const msg::Odometry* at_stop = nullptr;
    double max_drift_m = 0;
    for (const msg::Odometry& o : r.log->poses) {
      const double t = t_s(o.header);
      if (at_stop == nullptr && t >= 5.0 - 1e-6) at_stop = &o;
      if (at_stop != nullptr && t < 10.0 - 1e-6)
        max_drift_m = std::max(
            max_drift_m, std::hypot(o.T_world_body.position.x - at_stop->T_world_body.position.x,
                                    o.T_world_body.position.y - at_stop->T_world_body.position.y));
    }
    ASSERT_NE(at_stop, nullptr);
    EXPECT_GT(at_stop->T_world_body.position.x, -1.5) << kind;  // it was under way
    EXPECT_LT(max_drift_m, 0.05) << kind;
    bool stopped_reported = false;
    for (const msg::RobotState& s : r.log->states)
      if (t_s(s.header) > 5.5 && t_s(s.header) < 9.5)
        stopped_reported = stopped_reported || s.mode == msg::RobotState::Mode::kStopped;
    EXPECT_TRUE(stopped_reported) << kind;
    // after the resume it finishes the path
    EXPECT_EQ(r.tracker->plans_done(), 1u) << kind;
    EXPECT_LT(distance(r.log->poses.back(), path.back(), kind == "ground"), 0.1) << kind;
    std::printf("[figures] %s stop: drift after the stop %.3f m\n", kind.c_str(), max_drift_m);
  }
}

TEST(PathTracker, AStepAsideManeuverMovesTheRobotToTheAsidePoseThenItResumes) {
  for (const std::string kind : {"ground", "multirotor"}) {
    const std::vector<Waypoint4> path = {{-3, -2, 1, 0}, {3, -2, 1, 0}};
    const Waypoint4 aside = {-0.5, -1.0, 1.2, 90};
    TrackerRun r =
        run(launch_text(kind, {-3, -2, 1, 0}, 35.0, "{waypoints: " + list(path) + "}", "{}",
                        "{maneuvers: [4.0, 2, " + std::to_string(aside.x) + ", " +
                            std::to_string(aside.y) + ", " + std::to_string(aside.z) + ", " +
                            std::to_string(aside.yaw_deg) + ", 15.0, 0, 0, 0, 0, 0]}"));
    ASSERT_NE(r.tracker, nullptr);
    // at the aside pose before the resume, waiting there
    const msg::Odometry* before_resume = nullptr;
    for (const msg::Odometry& o : r.log->poses)
      if (t_s(o.header) < 15.0 - 1e-6) before_resume = &o;
    ASSERT_NE(before_resume, nullptr);
    const double aside_error_m = distance(*before_resume, aside, kind == "ground");
    EXPECT_LT(aside_error_m, 0.1) << kind;
    EXPECT_LT(yaw_error_deg(*before_resume, aside), 5.0) << kind;
    bool waiting = false;
    for (const msg::RobotState& s : r.log->states)
      if (t_s(s.header) > 14.0 && t_s(s.header) < 15.0 - 1e-6)
        waiting = s.mode == msg::RobotState::Mode::kWaiting;
    EXPECT_TRUE(waiting) << kind;
    EXPECT_EQ(r.tracker->plans_done(), 1u) << kind;
    EXPECT_LT(distance(r.log->poses.back(), path.back(), kind == "ground"), 0.1) << kind;
    std::printf("[figures] %s step aside: %.3f m, %.2f deg from the aside pose\n", kind.c_str(),
                aside_error_m, yaw_error_deg(*before_resume, aside));
  }
}

TEST(PathTracker, IgnoresAStalePlanAndStopsOnAnEmptyPath) {
  // plan 5 is followed; an older plan 3 arrives at 2 s (ignored), an empty plan 6 at 4 s
  const std::vector<Waypoint4> path = {{-3, -2, 0, 0}, {3, -2, 0, 0}};
  const std::string text = launch_text("ground", {-3, -2, 0, 0}, 8.0,
                                       "{plan_id: 5, period_s: 0, waypoints: " + list(path) + "}",
                                       "{}", "{empty_path_at_s: 4.0, empty_plan_id: 6}");
  // a second player with the stale plan
  const std::string stale =
      text +
      R"(  - {name: stale, type: path_player, params: {plan_id: 3, start_s: 2.0, period_s: 0, waypoints: [0, 0, 0, 0]}}
)";
  TrackerRun r = run(stale);
  ASSERT_NE(r.tracker, nullptr);
  EXPECT_EQ(r.tracker->stale_plans(), 1u);
  EXPECT_EQ(r.tracker->plan_id(), 6u);
  EXPECT_EQ(r.tracker->mode(), msg::RobotState::Mode::kIdle);
  double x_at_4 = 0;
  for (const msg::Odometry& o : r.log->poses)
    if (t_s(o.header) <= 4.0 + 1e-6) {
      x_at_4 = o.T_world_body.position.x;
    }
  EXPECT_GT(x_at_4, -2.0);  // it followed plan 5, not the stale plan 3 (behind it)
  for (const msg::VelocityCommand& c : r.log->commands)
    if (t_s(c.header) > 4.0 + 1e-6) {
      EXPECT_EQ(c.linear_mps.x, 0.0);
      EXPECT_EQ(c.yaw_rate_radps, 0.0);
    }
  // still from the first pose after the stop (poses come at 5 Hz)
  const msg::Odometry* after = nullptr;
  for (const msg::Odometry& o : r.log->poses)
    if (after == nullptr && t_s(o.header) > 4.0 + 1e-6) after = &o;
  ASSERT_NE(after, nullptr);
  EXPECT_LT(std::abs(r.log->poses.back().T_world_body.position.x - after->T_world_body.position.x),
            0.01);
}

TEST(PathTracker, HoldsStillOnNanPoses) {
  const std::vector<Waypoint4> path = {{-3, -2, 0, 0}, {3, -2, 0, 0}};
  TrackerRun r = run(launch_text("ground", {-3, -2, 0, 0}, 3.0, "{waypoints: " + list(path) + "}",
                                 "{}", "{nan_odom: true}", "odom"));
  ASSERT_NE(r.tracker, nullptr);
  EXPECT_EQ(r.tracker->mode(), msg::RobotState::Mode::kLost);
  ASSERT_FALSE(r.log->commands.empty());
  for (const msg::VelocityCommand& c : r.log->commands) {
    EXPECT_EQ(c.linear_mps.x, 0.0);
    EXPECT_EQ(c.yaw_rate_radps, 0.0);
  }
  EXPECT_NEAR(r.log->poses.back().T_world_body.position.x, -3.0, 1e-3);
}

// The odometry lost track: held still by default; with lost_turn_rate_radps a ground robot
// turns on the spot (no forward motion) after lost_turn_after_s at rest, until the odometry
// gives a pose again.
TEST(PathTracker, AGroundRobotWhoseOdometryLostTrackTurnsOnTheSpotWhenAsked) {
  const std::vector<Waypoint4> path = {{-3, -2, 0, 0}, {3, -2, 0, 0}};
  const std::string player = "{waypoints: " + list(path) + "}";
  TrackerRun held =
      run(launch_text("ground", {-3, -2, 0, 0}, 3.0, player, "{}", "{lost_odom: true}", "odom"));
  ASSERT_NE(held.tracker, nullptr);
  EXPECT_EQ(held.tracker->mode(), msg::RobotState::Mode::kLost);
  ASSERT_FALSE(held.log->commands.empty());
  for (const msg::VelocityCommand& c : held.log->commands) EXPECT_EQ(c.yaw_rate_radps, 0.0);

  TrackerRun turning = run(launch_text("ground", {-3, -2, 0, 0}, 3.0, player,
                                       "{lost_turn_rate_radps: 0.3, lost_turn_after_s: 1.0}",
                                       "{lost_odom: true}", "odom"));
  ASSERT_NE(turning.tracker, nullptr);
  EXPECT_EQ(turning.tracker->mode(), msg::RobotState::Mode::kLost);
  ASSERT_FALSE(turning.log->commands.empty());
  EXPECT_EQ(turning.log->commands.back().yaw_rate_radps, 0.3);
  for (const msg::VelocityCommand& c : turning.log->commands) {
    EXPECT_EQ(c.linear_mps.x, 0.0);
    // at rest for the first second (the first lost pose comes at 0 s)
    if (t_s(c.header) < 0.95) {
      EXPECT_EQ(c.yaw_rate_radps, 0.0) << t_s(c.header);
    }
  }
  // the simulator's truth: turned on the spot
  const msg::Odometry& last = turning.log->poses.back();
  EXPECT_GT(yaw_of(last), 0.4);  // 0.3 rad/s for the last ~2 s
  EXPECT_NEAR(last.T_world_body.position.x, -3.0, 0.02);
  EXPECT_NEAR(last.T_world_body.position.y, -2.0, 0.02);
}

TEST(PathTracker, AGroundRobotTurnsOnTheSpotFirstWhenAsked) {
  // a path straight ahead; the first scan turns a full circle before the robot drives
  const std::vector<Waypoint4> path = {{-3, -2, 0, 0}, {-1, -2, 0, 0}};
  const std::string player = "{waypoints: " + list(path) + "}";
  TrackerRun r = run(launch_text("ground", {-3, -2, 0, 0}, 25.0, player,
                                 "{initial_turn_deg: 360, ground_max_yaw_rate_radps: 0.5}", "{}"));
  ASSERT_NE(r.tracker, nullptr);
  ASSERT_FALSE(r.log->poses.empty());
  EXPECT_EQ(r.tracker->plans_done(), 1u);
  EXPECT_EQ(r.tracker->mode(), msg::RobotState::Mode::kDone);
  // turned on the spot (yaw accumulated from the truth) before it left its start
  double turned = 0, turned_when_left = -1;
  for (size_t i = 1; i < r.log->poses.size(); ++i) {
    turned +=
        std::abs(std::remainder(yaw_of(r.log->poses[i]) - yaw_of(r.log->poses[i - 1]), 2 * M_PI));
    if (turned_when_left < 0 && distance(r.log->poses[i], path.front(), true) > 0.05)
      turned_when_left = turned;
  }
  std::printf("[figures] first scan: turned %.0f deg before leaving the start, %.0f in all\n",
              turned_when_left * 180 / M_PI, turned * 180 / M_PI);
  EXPECT_GE(turned_when_left, 2 * M_PI - 0.05);
  for (const msg::VelocityCommand& c : r.log->commands) {
    if (t_s(c.header) >= 2 * M_PI / 0.5 - 0.5) continue;
    EXPECT_EQ(c.linear_mps.x, 0.0) << t_s(c.header);
    EXPECT_EQ(c.yaw_rate_radps, 0.5) << t_s(c.header);
  }
  EXPECT_LT(distance(r.log->poses.back(), path.back(), true), 0.1 + 1e-3);

  // the first scan is for ground robots: a multirotor flies its path at once
  TrackerRun air = run(launch_text("multirotor", {-3, -2, 1, 0}, 6.0,
                                   "{waypoints: [-3, -2, 1, 0, "
                                   "-1, -2, 1, 0]}",
                                   "{initial_turn_deg: 360}", "{}"));
  ASSERT_NE(air.tracker, nullptr);
  EXPECT_EQ(air.tracker->plans_done(), 1u);
}

TEST(PathTracker, TheExampleLaunchFileBringsBothRobotsToTheirGoals) {
  // launch_cfg/tracker_sim.yaml names its scene relative to the repository root
  const std::filesystem::path cwd = std::filesystem::current_path();
  std::filesystem::current_path(SCANCREW_SOURCE_DIR);
  auto launch = Launch::from_file("launch_cfg/tracker_sim.yaml");
  std::filesystem::current_path(cwd);
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  int trackers = 0;
  for (const auto& c : (*launch)->components()) {
    const auto* t = dynamic_cast<const PathTracker*>(c.get());
    if (t == nullptr) continue;
    ++trackers;
    EXPECT_EQ(t->plans_done(), 1u) << t->qualified_name();
    EXPECT_LE(t->done_position_error_m(), 0.1) << t->qualified_name();
    std::printf(
        "[figures] %s (%s): done at %.1f s, %.2f m travelled, %.3f m %.2f deg from the goal\n",
        t->qualified_name().c_str(), t->ground() ? "ground" : "multirotor",
        1e-9 * static_cast<double>(t->done_stamp_ns()), t->travelled_m(),
        t->done_position_error_m(), t->done_yaw_error_rad() * 180 / M_PI);
  }
  EXPECT_EQ(trackers, 2);
}

TEST(PathTracker, RefusesBadParameters) {
  const std::string path = "{waypoints: [0, 0, 0, 0]}";
  auto launch = Launch::from_string(
      launch_text("ground", {-3, -2, 0, 0}, 1.0, path, "{align_radius_m: 0.5}", "{}"), "bad.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("align_radius_m"), std::string::npos)
      << launch.error().front();
  launch = Launch::from_string(
      launch_text("ground", {-3, -2, 0, 0}, 1.0, "{waypoints: [1, 2, 3]}", "{}", "{}"), "bad.yaml");
  ASSERT_FALSE(launch);
  EXPECT_NE(launch.error().front().find("quadruples"), std::string::npos) << launch.error().front();
}

}  // namespace
}  // namespace scancrew::path_tracker
