#pragma once

// Visibility of ISEs from a viewpoint and the gain of a cluster (thesis 2.4.3, eq. 2.1).
//
// From the viewpoint's camera, rows × columns rays spread over the camera's FOV (level,
// along the viewpoint's yaw) are traced through the voxels (3D DDA) from the minimum to
// the maximum range. A ray stops at the first occupied or unknown voxel (it cannot see
// through either: occlusion); every ISE voxel it crosses before is seen. C_q is the set of
// ISEs seen from q; g(U) = |C_U| / |C| with C_U the union over U's viewpoints.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/ise/ise.hpp"
#include "core/ise/ise_config.hpp"
#include "core/ise/ise_index.hpp"
#include "core/ise/state_grid.hpp"

namespace scancrew::ise {

// The ISEs seen from a camera at `position` looking along `yaw_rad`, sorted, unique.
std::vector<uint32_t> visible_ises(const tsdf::MapSnapshot& snap, const IseIndex& ises,
                                   const RobotTypeSpec& type, int rows, int cols,
                                   const Eigen::Vector3d& position, double yaw_rad);
// The same on the map's compact states (state_grid.hpp): what IsePipeline calls.
std::vector<uint32_t> visible_ises(const StateGrid& states, double voxel_m, const IseIndex& ises,
                                   const RobotTypeSpec& type, int rows, int cols,
                                   const Eigen::Vector3d& position, double yaw_rad);

// The axis-aligned box (block indices, inclusive) that the rays of such a camera can reach.
void view_bounds(const RobotTypeSpec& type, const Eigen::Vector3d& position, double yaw_rad,
                 double block_m, BlockIndex& lo, BlockIndex& hi);

}  // namespace scancrew::ise
