#pragma once

// What the team simulator needs to know about a robot: its kind, where it starts, its
// stereo camera, its IMU. Plain structs, SI units, defaults from the thesis (tables 2.1,
// 3.1, 5.3; section 2.6.1).

#include <cstdint>
#include <string>

#include "core/robot/robot_kind.hpp"
#include "interfaces/geometry.hpp"

namespace scancrew::sim {

using robot::RobotKind;

struct CameraSpec {
  uint32_t width = 320, height = 185;  // square pixels: 90° x 60° needs width/height = tan45/tan30
  double fov_h_deg = 90.0, fov_v_deg = 60.0;
  double baseline_m = 0.26;  // 0.26 ground robots (5.2), 0.11 multirotors (table 2.1)
  double rate_hz = 5.0;
  double min_range_m = 0.3, max_range_m = 5.0;  // table 5.3; [1.6, 8] for the powerplant UAV
  double mount_forward_m = 0.25;                // left camera centre in the body frame
  double mount_up_m = 0.35;  // (ground robot: above the floor; multirotor: above the body centre)

  double fx_px() const;  // focal length MuJoCo renders with: from the vertical FOV and height
  // Empty when valid, else what is wrong (zero baseline, FOV out of range, aspect that
  // square pixels cannot give).
  std::string validate() const;
};

struct ImuSpec {
  double rate_hz = 100.0;
  double accel_noise_mps2 = 0.02;  // white noise, standard deviation per sample
  double gyro_noise_radps = 0.002;
};

struct DepthNoiseSpec {
  bool enabled = true;
  double disparity_error_px = 0.1;  // |e_d|, tables 2.1 / 3.1 / 4.1
  bool smoothing = true;            // 3x3 Gaussian after the noise (2.6.1)
};

struct RobotSpec {
  uint32_t id = 0;
  std::string name;  // the robot's namespace, e.g. "robot1"
  RobotKind kind = RobotKind::kGround;
  double start_x_m = 0, start_y_m = 0, start_z_m = 0, start_yaw_rad = 0;  // z: multirotor only
  double nominal_speed_mps = 0.5;  // 0.5 ground (table 5.3), 0.6 multirotor (2.6.1)
  CameraSpec camera;
  ImuSpec imu;
  DepthNoiseSpec depth_noise;
};

// The camera a robot of this kind carries unless its launch file says otherwise: the
// defaults of CameraSpec (ground robots, table 5.3) or, for multirotors, table 2.1's baseline
// (0.11 m) and range ([1.6, 8] m) with the camera at the body centre.
CameraSpec default_camera(RobotKind kind);

}  // namespace scancrew::sim
