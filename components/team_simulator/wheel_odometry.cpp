#include "components/team_simulator/wheel_odometry.hpp"

#include <cmath>

namespace scancrew::team_simulator {

double heading_of(const msg::Quat& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

WheelOdometry::WheelOdometry(const WheelOdometryConfig& config, uint64_t seed,
                             const msg::Pose3& start)
    : config_(config), rng_(seed) {
  std::normal_distribution<double> unit(0.0, 1.0);
  scale_ = 1.0 + unit(rng_) * config_.scale_sigma;
  x_ = start.position.x;
  y_ = start.position.y;
  z_ = start.position.z;
  yaw_ = heading_of(start.orientation);
}

msg::Odometry WheelOdometry::measure(int64_t stamp_ns, const msg::Vec3& velocity_world_mps,
                                     double yaw_rad, double yaw_rate_radps) {
  // dead reckoning over the interval with the previous reading's twist
  if (last_ns_ >= 0 && stamp_ns > last_ns_) {
    const double dt = static_cast<double>(stamp_ns - last_ns_) * 1e-9;
    const double c = std::cos(yaw_), s = std::sin(yaw_);
    x_ += (c * v_x_ - s * v_y_) * dt;
    y_ += (s * v_x_ + c * v_y_) * dt;
    yaw_ += w_z_ * dt;
  }
  last_ns_ = stamp_ns;
  std::normal_distribution<double> unit(0.0, 1.0);
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  const double vx = c * velocity_world_mps.x + s * velocity_world_mps.y;
  const double vy = -s * velocity_world_mps.x + c * velocity_world_mps.y;
  v_x_ = scale_ * vx + unit(rng_) * config_.speed_noise_mps;
  v_y_ = scale_ * vy + unit(rng_) * config_.speed_noise_mps;
  w_z_ = yaw_rate_radps + unit(rng_) * config_.yaw_rate_noise_radps;

  msg::Odometry odom;
  odom.header.stamp_ns = stamp_ns;
  odom.T_world_body.position = {x_, y_, z_};
  odom.T_world_body.orientation = {std::cos(yaw_ / 2), 0, 0, std::sin(yaw_ / 2)};
  odom.linear_velocity_mps = {v_x_, v_y_, 0};
  odom.angular_velocity_radps = {0, 0, w_z_};
  odom.tracking_quality = 1.0;
  return odom;
}

}  // namespace scancrew::team_simulator
