#pragma once

// Sensor messages: what the backends (sim, hardware, replay) publish and the perception
// components read. Image payloads are std::vector members: their capacity is kept when a
// pool slot is recycled, so steady-state publishing allocates nothing.

#include <cstdint>
#include <vector>

#include "interfaces/geometry.hpp"
#include "interfaces/header.hpp"

namespace scancrew::msg {

// A rectified grayscale stereo pair, row-major, 8 bits per pixel, left camera frame.
struct StereoFrame {
  static constexpr const char* kTypeName = "scancrew/StereoFrame";
  Header header;                // stamp: capture time
  CameraIntrinsics intrinsics;  // of the left (and, rectified, the right) image
  double baseline_m = 0;
  Pose3 T_body_cam;  // the left camera's optical frame (z forward, x right, y down) on the body
  std::vector<uint8_t> left, right;  // width*height each
};

struct Imu {
  static constexpr const char* kTypeName = "scancrew/Imu";
  Header header;
  Vec3 linear_acceleration_mps2;  // specific force in the IMU frame (reads +g up at rest)
  Vec3 angular_velocity_radps;
};

// Depth along the optical axis, metres; as ROS REP 117: NaN where unknown, +inf where
// nothing is within max_range_m (the mapper may clear that ray). Carries the camera pose
// at capture so a consumer needs no pose lookup.
struct DepthImage {
  static constexpr const char* kTypeName = "scancrew/DepthImage";
  Header header;
  CameraIntrinsics intrinsics;
  Pose3 T_world_cam;
  double min_range_m = 0, max_range_m = 0;
  std::vector<float> depth_m;  // width*height
};

}  // namespace scancrew::msg
