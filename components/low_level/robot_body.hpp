#pragma once

// RobotBody: the volume the low-level planner keeps out of occupied (and, by config,
// unknown) space — thesis 2.5.3 and 5.3: an ellipsoid for a ground robot, its greater
// semi-axis along the robot's heading (table 5.3: semi-axes 0.55 and 0.25 m), a sphere for
// a multirotor (table 2.1: collision radius 1 m). Plain geometry: no FCL here.

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>

#include "components/low_level/check_types.hpp"  // RobotKind

namespace scancrew::low_level {

struct RobotBody {
  RobotKind kind = RobotKind::kGround;
  // Ellipsoid semi-axes in the body frame (x forward, y left, z up), m; a sphere when all
  // three are equal. Any safety margin is already added.
  Eigen::Vector3d radii_m = Eigen::Vector3d(0.55, 0.25, 0.25);

  double bounding_radius_m() const { return radii_m.maxCoeff(); }

  // Half extents of the world-aligned box around the body turned by R (exact for an
  // ellipsoid: h_i = sqrt(sum_j (R_ij r_j)^2)).
  Eigen::Vector3d aabb_half_extents(const Eigen::Matrix3d& R) const {
    Eigen::Vector3d h;
    for (int i = 0; i < 3; ++i) h[i] = R.row(i).cwiseProduct(radii_m.transpose()).norm();
    return h;
  }
};

}  // namespace scancrew::low_level
