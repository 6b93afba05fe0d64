#pragma once

// Geometry shared by the messages: plain values, SI units, frames in the names of the
// fields that hold them (T_world_cam: the camera's pose in the world frame).

#include <array>
#include <cstdint>

namespace scancrew::msg {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

// Unit quaternion, Hamilton convention, w first.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

// A rigid transform T_a_b: maps points of frame b into frame a.
struct Pose3 {
  Vec3 position;  // m
  Quat orientation;
};

// Pinhole intrinsics of a rectified camera, pixels.
struct CameraIntrinsics {
  uint32_t width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

using Mat6 = std::array<double, 36>;  // row-major 6x6 covariance (x y z roll pitch yaw)

}  // namespace scancrew::msg
