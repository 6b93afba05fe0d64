#pragma once

// Synthetic depth frames for the mapping tests: a 160 × 120 camera with a 90° horizontal
// field of view looking along +x (camera z forward, x right, y down), seeing walls x = const.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/tsdf/integrator.hpp"

namespace scancrew::tsdf::test {

inline constexpr uint32_t kW = 160, kH = 120;
inline constexpr double kF = 80.0;

inline Eigen::Isometry3d looking_along_x(const Eigen::Vector3d& position) {
  Eigen::Matrix3d rotation;
  rotation.col(0) = Eigen::Vector3d(0, -1, 0);  // camera x: right
  rotation.col(1) = Eigen::Vector3d(0, 0, -1);  // camera y: down
  rotation.col(2) = Eigen::Vector3d(1, 0, 0);   // camera z: forward
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation;
  T.translation() = position;
  return T;
}

// Depth z everywhere; optionally a step: pixels with u ≥ step_u see a nearer wall z_near.
inline std::vector<float> wall_depth(double z, double step_u = kW, double z_near = 0) {
  std::vector<float> d(static_cast<size_t>(kW) * kH, static_cast<float>(z));
  for (uint32_t v = 0; v < kH; ++v)
    for (uint32_t u = 0; u < kW; ++u)
      if (u >= step_u) d[v * kW + u] = static_cast<float>(z_near);
  return d;
}

inline DepthFrame frame(const std::vector<float>& depth,
                        const Eigen::Isometry3d& T_world_cam = looking_along_x({0, 0, 0})) {
  DepthFrame f;
  f.depth_m = depth.data();
  f.size = depth.size();
  f.width = kW;
  f.height = kH;
  f.fx = f.fy = kF;
  f.cx = kW / 2.0;
  f.cy = kH / 2.0;
  f.T_world_cam = T_world_cam;
  return f;
}

}  // namespace scancrew::tsdf::test
