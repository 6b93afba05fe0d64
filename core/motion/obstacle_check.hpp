#pragma once

// ObstacleCheck (thesis 2.5.3 item 4; Algorithm 1 line 14, Algorithm 3 line 14, Algorithm 6
// line 18): an emergency stop when an occupied voxel enters the robot's safety volume.
// The volume is a sphere of the collision radius around an aerial robot (1 m, tables 2.1,
// 3.1, 4.1) and, around a ground robot, an ellipse whose semi-major axis lies along the
// robot's heading (0.55 m x 0.25 m, table 5.3).
//
// Choices where the thesis is silent (docs/traffic_policy.md):
// - a voxel counts when its centre lies in the volume grown by half a voxel, so a voxel that
//   reaches the volume's boundary is caught whatever the grid's alignment;
// - a ground robot only looks at voxels whose centres lie in a height band above its base
//   (min_height_m..max_height_m), so the floor it drives on never stops it.
//
// The map is a callable (check_types.hpp), so the check does not depend on the map type.
// Deterministic: voxels are visited in a fixed order. No allocation; any thread (the query
// decides its own thread safety).

#include <Eigen/Core>
#include <cstddef>
#include <string>

#include "core/motion/check_types.hpp"

namespace scancrew::motion {

struct ObstacleCheckConfig {
  RobotKind kind = RobotKind::kGround;
  // for_kind() takes these three from the kind's robot::BodyModel
  double sphere_radius_m = 1.0;  // aerial: collision radius (tables 2.1, 3.1, 4.1)
  double semi_major_m = 0.55;    // ground: along the heading (table 5.3, "sM")
  double semi_minor_m = 0.25;    // ground: across the heading (table 5.3, "sm")
  // ground: the band above the robot's base (its position's z) where voxels count; the
  // default keeps floor voxels (centres below 0.1 m) out and covers the body and the camera
  // (0.35 m above the floor, sim/robot_model.hpp)
  double min_height_m = 0.1;
  double max_height_m = 0.5;
  // Upper bound on the voxels one check may visit; a voxel size too small for the volume
  // is reported, not looped over.
  size_t max_voxels = 2'000'000;

  // The kind's safety volume (its BodyModel) and the defaults above.
  static ObstacleCheckConfig for_kind(RobotKind kind);
  // Empty when valid, else every problem, "; "-separated.
  std::string validate() const;
};

enum class ObstacleStatus : uint8_t {
  kClear,     // no occupied voxel in the safety volume
  kObstacle,  // emergency stop (obstacle = True)
  kBadInput,  // non-finite pose, voxel size <= 0, or too many voxels: treat as a stop
};
const char* to_string(ObstacleStatus status);

struct ObstacleCheckResult {
  ObstacleStatus status = ObstacleStatus::kClear;
  bool stop() const { return status != ObstacleStatus::kClear; }
  // the occupied voxel centre deepest in the volume (smallest normalised radius), and its
  // distance from the robot's position (planar for ground robots)
  Eigen::Vector3d nearest_occupied = Eigen::Vector3d::Zero();
  double nearest_distance_m = 0;
  size_t voxels_checked = 0;
};

// ObstacleCheck(q_curr, M). `voxel_m` is the map's voxel size; voxel centres lie at
// (i + 0.5)·voxel_m, as in the TSDF map (core/tsdf/block.hpp).
ObstacleCheckResult obstacle_check(const Eigen::Vector3d& position, double yaw_rad, double voxel_m,
                                   const OccupancyQuery& occupied,
                                   const ObstacleCheckConfig& config);

}  // namespace scancrew::motion
