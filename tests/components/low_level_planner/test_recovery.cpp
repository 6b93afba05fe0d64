// Recovery, the low-level planner's ways out (recovery.hpp), on hand-made geometry: each
// expected pose or distance is worked out from the rings and the walls below, not from
// the code.

#include <gtest/gtest.h>

#include <cmath>

#include "components/low_level_planner/recovery.hpp"

namespace scancrew::low_level_planner {
namespace {

msg::Waypoint at(double x, double y, double z = 0, double yaw = 0) {
  msg::Waypoint w;
  w.position = {x, y, z};
  w.yaw_rad = yaw;
  return w;
}

TEST(Recovery, BacksOffBehindTheRobotOnTheFirstFreeRing) {
  // rings 0.1 m apart from 0.2 m; a robot at the origin facing +x with a wall everywhere
  // but x <= -0.35: the first free pose is straight behind, on the 0.4 m ring
  const Recovery r(RecoveryConfig{});
  const auto free_behind = [](const msg::Waypoint& w) { return w.position.x <= -0.35; };
  const auto pose = r.escape_pose(at(0, 0), 0.2, false, 100, free_behind);
  ASSERT_TRUE(pose.has_value());
  EXPECT_NEAR(pose->position.x, -0.4, 1e-9);
  EXPECT_NEAR(pose->position.y, 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(pose->yaw_rad, 0.0);  // backs off: the heading is kept
  // nothing free within backoff_max_m (1 m): no pose
  const auto far = [](const msg::Waypoint& w) { return w.position.x <= -1.5; };
  EXPECT_FALSE(r.escape_pose(at(0, 0), 0.2, false, 100, far).has_value());
}

TEST(Recovery, AMultirotorClimbsFirstButNotAboveItsBand) {
  const Recovery r(RecoveryConfig{});
  const auto anywhere = [](const msg::Waypoint&) { return true; };
  const auto up = r.escape_pose(at(0, 0, 5), 0.2, true, 40, anywhere);
  ASSERT_TRUE(up.has_value());
  EXPECT_NEAR(up->position.z, 5.2, 1e-9);
  EXPECT_NEAR(up->position.x, 0.0, 1e-9);
  // at the top of the band (40 m) it goes sideways instead
  const auto side = r.escape_pose(at(0, 0, 40), 0.2, true, 40, anywhere);
  ASSERT_TRUE(side.has_value());
  EXPECT_DOUBLE_EQ(side->position.z, 40.0);
  EXPECT_NEAR(std::hypot(side->position.x, side->position.y), 0.2, 1e-9);
}

TEST(Recovery, NudgesAGoalToTheNearestFreePoseWithinItsLimit) {
  // goal_nudge_max_m 0.3, rings 0.1 m, 16 directions: free for y >= 0.19 is first met on
  // the 0.2 m ring straight left (at 67.5 degrees that ring reaches 0.2 sin 67.5 = 0.185);
  // free only beyond 0.3 m gives none
  const Recovery r(RecoveryConfig{});
  const auto left =
      r.nudged_goal(at(1, 1, 0, 0.7), [](const msg::Waypoint& w) { return w.position.y >= 1.19; });
  ASSERT_TRUE(left.has_value());
  EXPECT_NEAR(left->position.x, 1.0, 1e-9);
  EXPECT_NEAR(left->position.y, 1.2, 1e-9);
  EXPECT_DOUBLE_EQ(left->yaw_rad, 0.7);
  EXPECT_FALSE(r.nudged_goal(at(1, 1), [](const msg::Waypoint& w) {
                  return w.position.y >= 1.35;
                }).has_value());
}

TEST(Recovery, StuckRoundsBackOffFartherEachTimeFromOneSpot) {
  RecoveryConfig c;
  c.max_consecutive_failures = 3;
  c.stuck_backoff_m = 0.5;
  Recovery r(c);
  const Eigen::Vector3d spot(2, 0, 0);
  EXPECT_FALSE(r.count_no_path(spot));
  EXPECT_FALSE(r.count_no_path(spot));
  const auto first = r.count_no_path(spot);  // the third failure: round 1
  ASSERT_TRUE(first.has_value());
  EXPECT_DOUBLE_EQ(first->from_m, 0.5);
  EXPECT_FALSE(r.count_no_path(spot + Eigen::Vector3d(0.3, 0, 0)));  // still the same spot
  EXPECT_FALSE(r.count_no_path(spot));
  const auto second = r.count_no_path(spot);
  ASSERT_TRUE(second.has_value());
  EXPECT_DOUBLE_EQ(second->from_m, 1.0);
  // a failure 5 m away starts a new run; a path found forgets it
  EXPECT_FALSE(r.count_no_path(spot + Eigen::Vector3d(5, 0, 0)));
  r.path_found();
  EXPECT_FALSE(r.count_no_path(spot));
  EXPECT_FALSE(r.count_no_path(spot));
  EXPECT_DOUBLE_EQ(r.count_no_path(spot).value().from_m, 0.5);
  // stuck_backoff_m 0: never
  Recovery off(RecoveryConfig{});
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(off.count_no_path(spot));
}

TEST(Recovery, TheSecondStallOnOneGoalAtOneSpotSkipsIt) {
  Recovery r(RecoveryConfig{});
  const Eigen::Vector3d here(0, 0, 0);
  EXPECT_FALSE(r.stalled_again(7, 2, here));
  EXPECT_TRUE(r.stalled_again(7, 2, here + Eigen::Vector3d(0.5, 0, 0)));  // within 1 m
  EXPECT_FALSE(r.stalled_again(7, 2, here));                             // forgotten after the skip
  EXPECT_FALSE(r.stalled_again(7, 3, here));                             // another goal
  EXPECT_FALSE(r.stalled_again(7, 3, here + Eigen::Vector3d(3, 0, 0)));  // elsewhere
}

TEST(Recovery, AGoalIsOverItsDetourBudgetPastTwiceItsFirstPathPlusTheHorizon) {
  // first path 10 m: the budget is 2 x 10 + 5 = 25 m of way (travelled since, plus left)
  Recovery r(RecoveryConfig{});
  EXPECT_FALSE(r.over_detour_budget(1, 0, 100, 10, 9));       // records the first path
  EXPECT_FALSE(r.over_detour_budget(1, 0, 115, 12, 10));      // 15 + 10 = 25: within
  const auto over = r.over_detour_budget(1, 0, 116, 12, 10);  // 26
  ASSERT_TRUE(over.has_value());
  EXPECT_DOUBLE_EQ(over->way_m, 26);
  EXPECT_DOUBLE_EQ(over->budget_m, 25);
  EXPECT_DOUBLE_EQ(over->first_m, 10);
  EXPECT_FALSE(r.over_detour_budget(1, 1, 116, 30, 20));  // a new goal: a new record
}

}  // namespace
}  // namespace scancrew::low_level_planner
