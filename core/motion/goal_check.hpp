#pragma once

// GoalReached (thesis 2.5.3 item 2; Algorithm 1 line 13, Algorithm 3 line 13, Algorithm 6
// line 17): the path to goal q has been travelled when the robot's pose is within a
// position and a yaw tolerance of q. The thesis gives no tolerances: ours are in
// GoalCheckConfig (docs/traffic_policy.md). Ground robots compare positions in the plane,
// aerial robots in 3D. Pure functions, no allocation, any thread.

#include <Eigen/Core>

#include "core/motion/check_types.hpp"

namespace scancrew::motion {

struct GoalCheckConfig {
  // A viewpoint is a camera pose: close enough that the ISEs it was chosen for are still in
  // range (δ_pose is 1.3-4.7 m, tables 4.1, 5.3) and about one voxel (0.1-0.3 m) off.
  double position_tolerance_m = 0.25;
  // Yaw error allowed at the goal; with a 90° horizontal FOV (table 5.3) an ISE centred at
  // the goal stays 30° inside the image. Ignored when check_yaw is false.
  double yaw_tolerance_deg = 15.0;
  bool check_yaw = true;
};

// Angle wrapped to (-π, π].
double wrap_angle(double angle_rad);

// Distance from `position` to `goal`: planar for ground robots, 3D for aerial ones.
double goal_distance_m(RobotKind kind, const Eigen::Vector3d& position,
                       const Eigen::Vector3d& goal);

// GoalReached(q_curr, q).
bool goal_reached(RobotKind kind, const Eigen::Vector3d& position, double yaw_rad,
                  const Eigen::Vector3d& goal, double goal_yaw_rad, const GoalCheckConfig& config);

// An idle robot sent to an aside point `sent_ago_s` ago is still on its way there: farther
// from it than the position tolerance, measured as GoalReached measures (a multirotor sent
// straight up or down is not there at once), and sent less than `max_wait_s` ago. False on
// non-finite input (the caller then decides again).
bool aside_on_the_way(RobotKind kind, const Eigen::Vector3d& position,
                      const Eigen::Vector3d& aside_point, double sent_ago_s,
                      const GoalCheckConfig& config, double max_wait_s);

}  // namespace scancrew::motion
