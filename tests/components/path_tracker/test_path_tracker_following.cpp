// The path tracker on the sim backend (tracker_harness.hpp) following paths: a ground robot
// and a multirotor follow a path through a sequence of waypoints and stop at the last within
// tolerance; a ground robot backs off to a pose just behind it, reaches goals behind and
// aside without dithering, and follows a path that doubles back beside it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "tests/components/path_tracker/tracker_harness.hpp"

namespace scancrew::path_tracker {
namespace {

using namespace testing;  // NOLINT(google-build-using-namespace): the harness

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

}  // namespace
}  // namespace scancrew::path_tracker
