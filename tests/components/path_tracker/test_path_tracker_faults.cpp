// The path tracker on faulty input, on the sim backend (tracker_harness.hpp): stale plans,
// empty paths and NaN poses stop it safely; when the odometry lost track it holds still, or
// turns on the spot when asked.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "tests/components/path_tracker/tracker_harness.hpp"

namespace scancrew::path_tracker {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

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

}  // namespace
}  // namespace scancrew::path_tracker
