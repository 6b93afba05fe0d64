#include "core/motion/goal_check.hpp"

#include <cmath>
#include <numbers>

namespace scancrew::motion {

double wrap_angle(double angle_rad) {
  if (!std::isfinite(angle_rad)) return angle_rad;
  double a = std::remainder(angle_rad, 2 * std::numbers::pi);  // [-π, π]
  if (a <= -std::numbers::pi) a += 2 * std::numbers::pi;
  return a;
}

double goal_distance_m(RobotKind kind, const Eigen::Vector3d& position,
                       const Eigen::Vector3d& goal) {
  const Eigen::Vector3d d = goal - position;
  return kind == RobotKind::kGround ? d.head<2>().norm() : d.norm();
}

bool goal_reached(RobotKind kind, const Eigen::Vector3d& position, double yaw_rad,
                  const Eigen::Vector3d& goal, double goal_yaw_rad, const GoalCheckConfig& config) {
  // a NaN anywhere compares false: never "reached" on bad input
  if (!(goal_distance_m(kind, position, goal) <= config.position_tolerance_m)) return false;
  if (!config.check_yaw) return true;
  const double yaw_error = std::abs(wrap_angle(goal_yaw_rad - yaw_rad));
  return yaw_error <= config.yaw_tolerance_deg * std::numbers::pi / 180.0;
}

bool aside_on_the_way(RobotKind kind, const Eigen::Vector3d& position,
                      const Eigen::Vector3d& aside_point, double sent_ago_s,
                      const GoalCheckConfig& config, double max_wait_s) {
  return goal_distance_m(kind, position, aside_point) > config.position_tolerance_m &&
         sent_ago_s < max_wait_s;
}

}  // namespace scancrew::motion
