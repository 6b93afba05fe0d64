// recheck_path (path_recheck.hpp): the part of a local path ahead of the robot against a
// newer map, given as an is_free callable.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/motion/goal_check.hpp"
#include "core/motion/path_recheck.hpp"

namespace scancrew::motion {
namespace {

msg::Waypoint wp(double x, double y, double yaw = 0) {
  return {.position = {x, y, 0}, .yaw_rad = yaw};
}

// free everywhere except x in [lo, hi]
auto wall_across_x(double lo, double hi) {
  return [lo, hi](const msg::Waypoint& w) { return w.position.x < lo || w.position.x > hi; };
}

TEST(PathRecheck, FindsTheFirstBlockedPoseAheadOfTheRobot) {
  const std::vector<msg::Waypoint> path = {wp(0, 0), wp(2, 0), wp(4, 0)};
  const PathRecheck r = recheck_path(path, {1.0, 0.05, 0}, 5.0, 0.1, wall_across_x(3.0, 3.2));
  ASSERT_TRUE(r.blocked);
  EXPECT_NEAR(r.where.x(), 3.0, 0.1 + 1e-9);
  EXPECT_NEAR(r.blocked_at_m, 2.0, 0.1 + 1e-9);  // from the robot's projection at x = 1
}

TEST(PathRecheck, LooksNoFurtherThanTheHorizon) {
  const std::vector<msg::Waypoint> path = {wp(0, 0), wp(2, 0), wp(4, 0)};
  const PathRecheck r = recheck_path(path, {1.0, 0, 0}, 1.5, 0.1, wall_across_x(3.0, 3.2));
  EXPECT_FALSE(r.blocked);
  EXPECT_GE(r.poses_checked, 14u);
  EXPECT_LE(r.poses_checked, 16u);
}

TEST(PathRecheck, IgnoresWhatLiesBehindOrUnderTheRobot) {
  const std::vector<msg::Waypoint> path = {wp(0, 0), wp(2, 0), wp(4, 0)};
  EXPECT_FALSE(recheck_path(path, {1.0, 0, 0}, 5.0, 0.1, wall_across_x(0.4, 0.6)).blocked);
  // the robot's projection (x = 1) is not checked, the next sample is
  EXPECT_FALSE(recheck_path(path, {1.0, 0, 0}, 5.0, 0.1, wall_across_x(0.97, 1.03)).blocked);
  EXPECT_TRUE(recheck_path(path, {1.0, 0, 0}, 5.0, 0.1, wall_across_x(1.07, 1.13)).blocked);
}

TEST(PathRecheck, ChecksTheGoalAndEveryWaypointOnTheWay) {
  // the goal only: blocked there although the samples between would miss a thin obstacle
  const std::vector<msg::Waypoint> path = {wp(0, 0), wp(1, 0), wp(1.05, 0)};
  const PathRecheck r = recheck_path(path, {0, 0, 0}, 5.0, 0.3, wall_across_x(1.04, 1.06));
  ASSERT_TRUE(r.blocked);
  EXPECT_DOUBLE_EQ(r.where.x(), 1.05);
  EXPECT_TRUE(recheck_path({{wp(2, 0)}}, {0, 0, 0}, 5.0, 0.1, wall_across_x(1.9, 2.1)).blocked);
}

TEST(PathRecheck, InterpolatesTheYawTheShortWay) {
  // from 3.0 rad to -3.0 rad: across pi (0.28 rad), not through 0 (6 rad)
  const std::vector<msg::Waypoint> path = {wp(0, 0, 3.0), wp(1, 0, -3.0)};
  double worst = 0;
  const PathRecheck r = recheck_path(path, {0, 0, 0}, 5.0, 0.1, [&](const msg::Waypoint& w) {
    worst = std::max(worst, std::abs(wrap_angle(w.yaw_rad - std::numbers::pi)));
    return true;
  });
  EXPECT_FALSE(r.blocked);
  EXPECT_GE(r.poses_checked, 10u);
  EXPECT_LE(worst, 0.1416 + 1e-6);
}

TEST(PathRecheck, NothingToCheckOnEmptyPathsOrBadSteps) {
  const auto never = [](const msg::Waypoint&) { return false; };
  EXPECT_EQ(recheck_path({}, {0, 0, 0}, 5.0, 0.1, never).poses_checked, 0u);
  const std::vector<msg::Waypoint> path = {wp(0, 0), wp(1, 0)};
  EXPECT_EQ(recheck_path(path, {0, 0, 0}, 5.0, 0.0, never).poses_checked, 0u);
  EXPECT_EQ(recheck_path(path, {0, 0, 0}, 0.0, 0.1, never).poses_checked, 0u);
}

TEST(PathRecheck, TheFirstWaypointAheadEndsTheNearestSegment) {
  // an L: along x to (2, 0), then up y to (2, 2)
  const std::vector<msg::Waypoint> path = {wp(0, 0), wp(2, 0), wp(2, 2)};
  EXPECT_EQ(first_waypoint_ahead(path, {1.0, 0.1, 0}), 1u);
  EXPECT_EQ(first_waypoint_ahead(path, {2.1, 1.0, 0}), 2u);
  EXPECT_EQ(first_waypoint_ahead({{wp(1, 1)}}, {0, 0, 0}), 0u);
}

}  // namespace
}  // namespace scancrew::motion
