// GoalReached and UtilityCheck (thesis 2.5.3 items 2 and 3).

#include <gtest/gtest.h>

#include <limits>
#include <numbers>
#include <vector>

#include "core/motion/goal_check.hpp"
#include "core/motion/utility_check.hpp"

namespace scancrew::motion {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(GoalCheck, ReachedWithinThePositionAndYawTolerances) {
  const GoalCheckConfig c;  // 0.25 m, 15 deg
  const Eigen::Vector3d goal(2, 1, 0);
  EXPECT_TRUE(goal_reached(RobotKind::kGround, {2.2, 1.1, 0}, 0.1, goal, 0.0, c));
  EXPECT_FALSE(goal_reached(RobotKind::kGround, {2.3, 1.0, 0}, 0.0, goal, 0.0, c));
  EXPECT_FALSE(goal_reached(RobotKind::kGround, {2.0, 1.0, 0}, 0.3, goal, 0.0, c));
  GoalCheckConfig no_yaw = c;
  no_yaw.check_yaw = false;
  EXPECT_TRUE(goal_reached(RobotKind::kGround, {2.0, 1.0, 0}, 3.0, goal, 0.0, no_yaw));
}

TEST(GoalCheck, GroundRobotsIgnoreHeightAerialOnesDoNot) {
  const GoalCheckConfig c;
  EXPECT_TRUE(goal_reached(RobotKind::kGround, {0, 0, 0.0}, 0, {0, 0, 1.0}, 0, c));
  EXPECT_FALSE(goal_reached(RobotKind::kMultirotor, {0, 0, 0.0}, 0, {0, 0, 1.0}, 0, c));
  EXPECT_TRUE(goal_reached(RobotKind::kMultirotor, {0, 0, 0.9}, 0, {0, 0, 1.0}, 0, c));
}

TEST(GoalCheck, YawErrorWrapsAroundPi) {
  const GoalCheckConfig c;
  EXPECT_TRUE(goal_reached(RobotKind::kGround, {0, 0, 0}, kPi - 0.1, {0, 0, 0}, -kPi + 0.1, c));
  EXPECT_NEAR(wrap_angle(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(wrap_angle(-kPi), kPi, 1e-12);
  EXPECT_NEAR(wrap_angle(-0.5), -0.5, 1e-12);
}

TEST(GoalCheck, NonFiniteInputIsNeverReached) {
  const GoalCheckConfig c;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(goal_reached(RobotKind::kGround, {nan, 0, 0}, 0, {0, 0, 0}, 0, c));
  EXPECT_FALSE(goal_reached(RobotKind::kGround, {0, 0, 0}, nan, {0, 0, 0}, 0, c));
}

TEST(GoalCheck, AMultirotorSentStraightUpIsOnItsWayUntilItClimbs) {
  // make_way's test: measured in the plane, an aside point 0.9 m straight up was "reached"
  // at once and the idle multirotor was sent aside again at every tick
  const GoalCheckConfig c;  // 0.25 m
  const Eigen::Vector3d aside(1, 2, 3.9);
  EXPECT_TRUE(aside_on_the_way(RobotKind::kMultirotor, {1, 2, 3.0}, aside, 0.1, c, 30));
  EXPECT_FALSE(aside_on_the_way(RobotKind::kMultirotor, {1, 2, 3.8}, aside, 2.0, c, 30));
  EXPECT_FALSE(aside_on_the_way(RobotKind::kGround, {1, 2, 3.0}, aside, 0.1, c, 30));
  EXPECT_TRUE(aside_on_the_way(RobotKind::kGround, {1, 1, 3.9}, aside, 0.1, c, 30));
  // past max_wait_s it decides again, wherever it is
  EXPECT_FALSE(aside_on_the_way(RobotKind::kMultirotor, {1, 2, 3.0}, aside, 30.0, c, 30));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(aside_on_the_way(RobotKind::kMultirotor, {nan, 2, 3.0}, aside, 0.1, c, 30));
}

TEST(UtilityCheck, AsksForANewTourOnceCThresOfTheStartIsesAreDone) {
  const UtilityCheckConfig c;  // 80 %, tables 2.1, 3.1, 4.1
  EXPECT_FALSE(utility_check(10, 10, c).update);
  EXPECT_FALSE(utility_check(10, 3, c).update);     // 70 %
  const UtilityStatus s = utility_check(10, 2, c);  // 80 %
  EXPECT_TRUE(s.update);
  EXPECT_DOUBLE_EQ(s.completed_fraction, 0.8);
  EXPECT_TRUE(utility_check(5, 1, c).update);  // 4 of 5
  EXPECT_TRUE(utility_check(10, 0, c).update);
  const UtilityCheckConfig sol{50.0};  // SoL, table 2.1
  EXPECT_FALSE(utility_check(10, 6, sol).update);
  EXPECT_TRUE(utility_check(10, 5, sol).update);
}

TEST(UtilityCheck, AnEmptyStartSetNeverAsksAndMoreLeftThanStartIsClamped) {
  const UtilityCheckConfig c;
  EXPECT_FALSE(utility_check(0, 0, c).update);
  EXPECT_FALSE(utility_check(0, 7, c).update);
  const UtilityStatus s = utility_check(4, 9, c);
  EXPECT_FALSE(s.update);
  EXPECT_DOUBLE_EQ(s.completed_fraction, 0.0);
}

TEST(UtilityCheck, CountsTheStartIsesThatAreStillIses) {
  const std::vector<uint64_t> start = {2, 5, 9, 14, 20};
  const std::vector<uint64_t> now = {1, 5, 6, 14, 30};  // 5 and 14 left, 1, 6, 30 are new
  EXPECT_EQ(count_remaining(start, now), 2u);
  EXPECT_EQ(count_remaining(start, {}), 0u);
  EXPECT_EQ(count_remaining({}, now), 0u);
  EXPECT_EQ(count_remaining(start, start), 5u);
  // the tour arrived with 5 ISEs, 3 done: 60 %, below c_thres
  EXPECT_FALSE(utility_check(start.size(), count_remaining(start, now), {}).update);
}

}  // namespace
}  // namespace scancrew::motion
