// ObstacleCheck (thesis 2.5.3 item 4): the safety ellipse of a ground robot (0.55 x 0.25 m,
// table 5.3), the 1 m sphere of a multirotor (table 4.1), and closed-loop runs where an
// obstacle appears ahead of a robot at cruise speed: the emergency stop fires before
// contact. The [figures] lines are quoted in docs/traffic_policy.md.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include "core/motion/obstacle_check.hpp"

namespace scancrew::motion {
namespace {

// occupied inside the boxes
OccupancyQuery boxes(std::vector<Eigen::AlignedBox3d> list) {
  return [list = std::move(list)](const Eigen::Vector3d& p) {
    for (const auto& b : list)
      if (b.contains(p)) return true;
    return false;
  };
}
// a single occupied voxel (0.1 m grid) holding point p
OccupancyQuery voxel_at(const Eigen::Vector3d& p, double h = 0.1) {
  const Eigen::Vector3d lo = (p / h).array().floor().matrix() * h;
  return boxes({Eigen::AlignedBox3d(lo, lo + Eigen::Vector3d::Constant(h))});
}

const ObstacleCheckConfig kGround = ObstacleCheckConfig::for_kind(RobotKind::kGround);
const ObstacleCheckConfig kMultirotor = ObstacleCheckConfig::for_kind(RobotKind::kMultirotor);

TEST(ObstacleCheck, TheGroundEllipseIsLongAlongTheHeading) {
  const Eigen::Vector3d at(1, 1, 0);
  // 0.5 m ahead: inside the 0.55 m semi-major axis
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({1.52, 1.02, 0.25}), kGround).status,
            ObstacleStatus::kObstacle);
  // 0.5 m to the side: outside the 0.25 m semi-minor axis
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({1.02, 1.52, 0.25}), kGround).status,
            ObstacleStatus::kClear);
  // turn the robot by 90 degrees: now the side one is ahead
  EXPECT_EQ(
      obstacle_check(at, std::numbers::pi / 2, 0.1, voxel_at({1.02, 1.52, 0.25}), kGround).status,
      ObstacleStatus::kObstacle);
  // 0.7 m ahead: clear
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({1.72, 1.02, 0.25}), kGround).status,
            ObstacleStatus::kClear);
}

TEST(ObstacleCheck, AGroundRobotIgnoresTheFloorAndWhatIsAboveItsBody) {
  const Eigen::Vector3d at(0.05, 0.05, 0);
  // a floor slab under the robot: voxels centred at z = -0.05
  const OccupancyQuery floor =
      boxes({Eigen::AlignedBox3d(Eigen::Vector3d(-5, -5, -0.1), Eigen::Vector3d(5, 5, 0.0))});
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, floor, kGround).status, ObstacleStatus::kClear);
  // a beam 1 m up, right above it
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({0.2, 0.05, 1.0}), kGround).status,
            ObstacleStatus::kClear);
  // a 15 cm step ahead is an obstacle
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({0.45, 0.05, 0.12}), kGround).status,
            ObstacleStatus::kObstacle);
}

TEST(ObstacleCheck, TheAerialSphereHasTheCollisionRadius) {
  const Eigen::Vector3d at(0.05, 0.05, 2.05);
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({0.05, 0.05, 1.1}), kMultirotor).status,
            ObstacleStatus::kObstacle);  // 0.95 m below
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({-0.9, 0.05, 2.05}), kMultirotor).status,
            ObstacleStatus::kObstacle);  // 0.95 m behind
  EXPECT_EQ(obstacle_check(at, 0.0, 0.1, voxel_at({1.25, 0.05, 2.05}), kMultirotor).status,
            ObstacleStatus::kClear);  // 1.2 m ahead
}

TEST(ObstacleCheck, ReportsTheDeepestOccupiedVoxel) {
  const OccupancyQuery two =
      boxes({Eigen::AlignedBox3d(Eigen::Vector3d(0.4, 0, 0.2), Eigen::Vector3d(0.5, 0.1, 0.3)),
             Eigen::AlignedBox3d(Eigen::Vector3d(0.2, 0, 0.2), Eigen::Vector3d(0.3, 0.1, 0.3))});
  const ObstacleCheckResult r = obstacle_check({0.05, 0.05, 0}, 0.0, 0.1, two, kGround);
  ASSERT_TRUE(r.stop());
  EXPECT_NEAR(r.nearest_occupied.x(), 0.25, 1e-9);
  EXPECT_NEAR(r.nearest_distance_m, 0.2, 1e-9);
  EXPECT_GT(r.voxels_checked, 0u);
}

TEST(ObstacleCheck, BadInputStopsTheRobotWithAStatusNotACrash) {
  const OccupancyQuery none = boxes({});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(obstacle_check({nan, 0, 0}, 0, 0.1, none, kGround).status, ObstacleStatus::kBadInput);
  EXPECT_EQ(obstacle_check({0, 0, 0}, nan, 0.1, none, kGround).status, ObstacleStatus::kBadInput);
  EXPECT_EQ(obstacle_check({0, 0, 0}, 0, 0.0, none, kGround).status, ObstacleStatus::kBadInput);
  EXPECT_EQ(obstacle_check({0, 0, 0}, 0, 0.1, OccupancyQuery{}, kGround).status,
            ObstacleStatus::kBadInput);
  // a voxel size far too small for the volume: refused, not looped over
  EXPECT_EQ(obstacle_check({0, 0, 0}, 0, 1e-6, none, kMultirotor).status,
            ObstacleStatus::kBadInput);
  EXPECT_EQ(obstacle_check({1e300, 0, 0}, 0, 0.1, none, kMultirotor).status,
            ObstacleStatus::kBadInput);
  ObstacleCheckConfig bad = kGround;
  bad.semi_major_m = 0.1;  // < semi-minor
  EXPECT_FALSE(bad.validate().empty());
  EXPECT_EQ(obstacle_check({0, 0, 0}, 0, 0.1, none, bad).status, ObstacleStatus::kBadInput);
  EXPECT_TRUE(kGround.validate().empty());
  EXPECT_TRUE(kMultirotor.validate().empty());
}

// Closed loop: a robot cruising along +x; a wall (x >= wall_x, 2 m wide, 1 m high) appears
// when the robot's centre is `appear_m` before it. The check runs every tick; its stop is
// applied from the next tick on, braking at `decel`. Returns the final gap between the
// body's front (half_length ahead of the centre) and the wall; negative: contact.
struct StopRun {
  double gap_m = 0;
  bool fired = false;
  double fired_at_distance_m = 0;  // centre to wall when the stop fired
};
StopRun emergency_stop_run(const ObstacleCheckConfig& c, double speed, double appear_m,
                           double half_length_m, double voxel_m, double z) {
  const double dt = 0.05, decel = 1.0, wall_x = 10.0;
  const OccupancyQuery wall = boxes({Eigen::AlignedBox3d(Eigen::Vector3d(wall_x, -1, z - 1),
                                                         Eigen::Vector3d(wall_x + 0.5, 1, z + 1))});
  const OccupancyQuery nothing = boxes({});
  double x = wall_x - appear_m - 1.0, v = speed;
  bool stop = false;
  StopRun out;
  for (int tick = 0; tick < 2000 && (v > 0 || !stop); ++tick) {
    // the check on this tick's pose, the command on the next
    const bool visible = x >= wall_x - appear_m;
    const ObstacleCheckResult r =
        obstacle_check({x, 0.0, z}, 0.0, voxel_m, visible ? wall : nothing, c);
    if (stop) v = std::max(0.0, v - decel * dt);
    x += v * dt;
    if (r.stop() && !stop) {
      stop = true;
      out.fired = true;
      out.fired_at_distance_m = wall_x - (x - v * dt);
    }
  }
  out.gap_m = wall_x - (x + half_length_m);
  return out;
}

TEST(ObstacleCheckSim, TheEmergencyStopFiresBeforeContactForAnObstacleAppearingAhead) {
  // ground robot, 0.5 m/s (table 5.3), body half length 0.22 m (sim/robot_model.hpp); the
  // wall appears far ahead, or already inside the 0.55 m ellipse
  for (const double voxel : {0.1, 0.2}) {
    for (const double appear : {3.0, 0.5, 0.45}) {
      const StopRun r = emergency_stop_run(kGround, 0.5, appear, 0.22, voxel, 0.0);
      std::printf(
          "[figures] ground 0.5 m/s, voxel %.1f m, wall appears %.2f m ahead: stop at "
          "%.2f m, final gap %.3f m\n",
          voxel, appear, r.fired_at_distance_m, r.gap_m);
      EXPECT_TRUE(r.fired);
      EXPECT_GT(r.gap_m, 0.0) << "contact, voxel " << voxel << ", appear " << appear;
    }
  }
  // multirotor, 0.6 m/s (2.6.1), half size 0.25 m, sphere 1 m
  for (const double appear : {3.0, 1.1}) {
    const StopRun r = emergency_stop_run(kMultirotor, 0.6, appear, 0.25, 0.3, 2.0);
    std::printf(
        "[figures] multirotor 0.6 m/s, voxel 0.3 m, wall appears %.1f m ahead: stop at "
        "%.2f m, final gap %.3f m\n",
        appear, r.fired_at_distance_m, r.gap_m);
    EXPECT_TRUE(r.fired);
    EXPECT_GT(r.gap_m, 0.0);
  }
}

TEST(ObstacleCheckSim, NothingFiresWhenPassingAWallBesideTheRobot) {
  // a wall parallel to the path, 0.45 m from the centre line (beyond the 0.25 m semi-minor)
  const OccupancyQuery wall =
      boxes({Eigen::AlignedBox3d(Eigen::Vector3d(0, 0.45, 0), Eigen::Vector3d(20, 0.6, 1))});
  for (double x = 1; x < 19; x += 0.05)
    ASSERT_FALSE(obstacle_check({x, 0.0, 0.0}, 0.0, 0.1, wall, kGround).stop()) << x;
}

}  // namespace
}  // namespace scancrew::motion
