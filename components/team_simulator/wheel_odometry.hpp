#pragma once

// WheelOdometry: what a ground robot's base reports from its wheel encoders, simulated: the
// body-frame velocity with a constant scale error per robot (tyre radius, slip) and white
// noise, the yaw rate the wheels imply with its own noise, and the pose dead-reckoned from
// them from the robot's start. A real base driver publishes the same (nav_msgs/Odometry:
// the twist in the body frame, the pose in its own odometry frame). The VIO reads the
// velocity as its motion prior and to coast through images without corners
// (docs/perception.md, "Wheel odometry").

#include <cstdint>
#include <random>

#include "interfaces/nav_msgs.hpp"

namespace scancrew::team_simulator {

struct WheelOdometryConfig {
  double rate_hz = 50.0;
  double scale_sigma = 0.02;           // the per-robot scale error's standard deviation
  double speed_noise_mps = 0.01;       // white noise per sample, each axis
  double yaw_rate_noise_radps = 0.02;  // the wheels' yaw rate is poorer than the gyro's
};

// The yaw of an orientation (rad), as the wheels know it: the heading they dead-reckon.
double heading_of(const msg::Quat& q);

class WheelOdometry {
 public:
  // seed: the robot's own stream (the simulator's other noise is not touched).
  WheelOdometry(const WheelOdometryConfig& config, uint64_t seed, const msg::Pose3& start);

  // One reading at stamp_ns from the true world-frame velocity, yaw and yaw rate; the pose
  // is integrated from the previous reading's noisy twist.
  msg::Odometry measure(int64_t stamp_ns, const msg::Vec3& velocity_world_mps, double yaw_rad,
                        double yaw_rate_radps);

  double scale() const { return scale_; }

 private:
  WheelOdometryConfig config_;
  std::mt19937_64 rng_;
  double scale_ = 1.0;
  double x_ = 0, y_ = 0, z_ = 0, yaw_ = 0;  // the dead-reckoned pose
  double v_x_ = 0, v_y_ = 0, w_z_ = 0;      // the last reading's body twist
  int64_t last_ns_ = -1;
};

}  // namespace scancrew::team_simulator
