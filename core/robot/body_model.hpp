#pragma once

// BodyModel: a robot's body, the one description every stage sizes its checks by.
//   - The simulator collides the frame (frame_half_m, a box) with the scene and the team
//     (sim/mjcf_builder.cpp).
//   - The low-level planner keeps the safety volume out of occupied (and, by config,
//     unknown) space (thesis 2.5.3 and 5.3): an ellipsoid with semi-axes safety_radii_m in
//     the body frame (x forward, y left, z up), its greater semi-axis along the heading for a
//     ground robot (table 5.3: 0.55 and 0.25 m), a sphere for a multirotor (table 2.1: 1 m).
//     A ground robot's ellipsoid is centred safety_center_z_m above the floor.
//   - ISE feasibility (core/ise/viewpoints.cpp) asks for a viewpoint's surroundings
//     to be free within the bounding radius (the safety volume in any heading) and, for a
//     ground robot, from the floor up to height_m.
//   - The evaluation's reachable ground truth (eval/free_space.hpp) drives the footprint
//     radius (the half width it needs along a passage, facing it) from underside_m to
//     height_m above the floor.
// The stages' tests differ (a voxel disc, an FCL ellipsoid, a grid cylinder: each suits its
// map); their sizes come from here. Plain geometry, SI units.

#include <Eigen/Core>

#include "core/robot/robot_kind.hpp"

namespace scancrew::robot {

struct BodyModel {
  RobotKind kind = RobotKind::kGround;
  // The frame's half extents (m): a Wifibot-like 0.44 x 0.40 x 0.20 m box for a ground robot,
  // a 0.50 x 0.50 x 0.20 m frame for a multirotor, inside their safety volumes.
  Eigen::Vector3d frame_half_m = Eigen::Vector3d(0.22, 0.20, 0.10);
  // The safety ellipsoid's semi-axes (m); table 5.3 gives 0.55 and 0.25 (the vertical one is
  // ours: the volume spans [centre_z - 0.25, centre_z + 0.25]).
  Eigen::Vector3d safety_radii_m = Eigen::Vector3d(0.55, 0.25, 0.25);
  // Ground robots: the ellipsoid's centre above the floor, clear of the floor voxels and low
  // enough to meet boxes 0.5 m tall; the body and camera's height (the camera is 0.35 m up);
  // the underside above the floor (lower steps are crossed).
  double safety_center_z_m = 0.5;
  double height_m = 0.4;
  double underside_m = 0.05;

  // The thesis's body of each kind (the values above for a ground robot).
  static BodyModel of(RobotKind kind);

  // The radius of the sphere that holds the safety volume in any heading.
  double bounding_radius_m() const { return safety_radii_m.maxCoeff(); }
  // The half width across the heading (ground: the minor semi-axis; multirotor: the radius).
  double footprint_radius_m() const { return safety_radii_m.head<2>().minCoeff(); }
  // Half extents of the world-aligned box around the safety volume turned by R (exact for an
  // ellipsoid: h_i = sqrt(sum_j (R_ij r_j)^2)).
  Eigen::Vector3d aabb_half_extents(const Eigen::Matrix3d& R) const;
  // The same body with margin_m added to every semi-axis.
  BodyModel inflated(double margin_m) const;
};

}  // namespace scancrew::robot
