#include "components/path_tracker/velocity_mapping.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace scancrew::path_tracker {

namespace {
double clamp_abs(double x, double limit) {
  return std::clamp(x, -limit, limit);
}
}  // namespace

UnicycleCommand to_unicycle(const LawOutput& law, const GroundMappingConfig& config, bool reverse,
                            bool final_pose) {
  const double d = std::hypot(law.offset_body_m.x(), law.offset_body_m.y());
  double alpha = d > 1e-9 ? std::atan2(law.offset_body_m.y(), law.offset_body_m.x()) : 0.0;
  // reversing: the heading error of the robot's back
  if (reverse) alpha = std::remainder(alpha - std::numbers::pi, 2 * std::numbers::pi);
  const double direction = reverse ? -1.0 : 1.0;

  // far: go to the point, slowing with the heading error, turning on the spot above a limit
  const double speed = std::min(std::hypot(law.twist.linear_mps.x(), law.twist.linear_mps.y()),
                                config.max_speed_mps);
  const double v_far =
      std::abs(alpha) > config.turn_in_place_rad ? 0.0 : direction * speed * std::cos(alpha);
  double omega_far = config.heading_gain * alpha;
  // backing: on arcs of at least reverse_min_radius_m, not turning on the spot
  if (reverse && config.reverse_min_radius_m > 0)
    omega_far = clamp_abs(omega_far, std::abs(v_far) / config.reverse_min_radius_m);
  // near: the twist's unicycle part (forward speed and yaw rate to the target's yaw)
  const double v_near = law.twist.linear_mps.x();
  const double omega_near = law.twist.angular_radps.z();

  const double r = final_pose ? config.align_radius_m : 0.0;  // on the way: the far law
  const double w = r > 0 ? std::clamp(2.0 * (r - d) / r, 0.0, 1.0) : 0.0;
  UnicycleCommand cmd;
  cmd.v_mps = clamp_abs((1 - w) * v_far + w * v_near, config.max_speed_mps);
  // the yaw rate is the near law's alone within the align radius (within the tracker's
  // position tolerance, so nothing is left to steer towards): a blend there had an
  // equilibrium with the target square to the side, the far law turning towards it and the
  // near law to the target's yaw, the robot standing still short of the yaw
  const double w_omega = d < r ? 1.0 : 0.0;
  cmd.omega_radps =
      clamp_abs((1 - w_omega) * omega_far + w_omega * omega_near, config.max_yaw_rate_radps);
  return cmd;
}

MultirotorCommand to_multirotor(const LawOutput& law, const MultirotorMappingConfig& config) {
  MultirotorCommand cmd;
  const Eigen::Vector3d& v = law.twist.linear_mps;
  double scale = 1.0;
  const double norm = v.norm();
  if (norm > config.max_speed_mps) scale = config.max_speed_mps / norm;
  if (std::abs(v.z()) * scale > config.max_vertical_speed_mps)
    scale = config.max_vertical_speed_mps / std::abs(v.z());
  cmd.linear_mps = v * scale;
  cmd.yaw_rate_radps = clamp_abs(law.twist.angular_radps.z(), config.max_yaw_rate_radps);
  return cmd;
}

}  // namespace scancrew::path_tracker
