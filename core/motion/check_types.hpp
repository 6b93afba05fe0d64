#pragma once

// Types shared by the low-level planner's decision checks (thesis 2.5.3, 3.5.2, 4.5.2):
// the kind of robot (which decides the safety volume of ObstacleCheck and whether traffic
// geometry is planar), and the map queries the checks take as callables so that they stay
// independent of the map type (adapters for tsdf::MapSnapshot: map_queries.hpp).
//
// Units: metres, radians, seconds; positions in the world frame.

#include <Eigen/Core>
#include <cstdint>
#include <functional>

#include "core/robot/robot_kind.hpp"

namespace scancrew::motion {

// Ground robots move in the plane (paths in 2D, safety ellipse); aerial robots (multirotors)
// in 3D (safety sphere). Thesis 2.5.3 item 1 and item 4.
using robot::RobotKind;

// True when the map voxel holding `point_world` is occupied (known and φ ≤ 0, thesis
// 1.3.3). Must be deterministic; called many times per check, from the caller's thread.
using OccupancyQuery = std::function<bool(const Eigen::Vector3d& point_world)>;

// True when the robot's body fits at `point_world` in free space (the caller's query
// accounts for the body size and for how unknown space is treated). Used to pick the
// traffic policy's step-aside point; deterministic, caller's thread.
using FreeSpaceQuery = std::function<bool(const Eigen::Vector3d& point_world)>;

}  // namespace scancrew::motion
