#pragma once

// Viewpoints (thesis 2.4.2): a sensor configuration at δ_pose from an ISE along its view
// direction, looking back at it; close, near-parallel ones merged by averaging.
//
// Our robots' cameras are body-fixed and level, so a viewpoint is a position and a yaw:
//   ground robots: the direction's horizontal part (the camera stays at its height above
//     the floor); the ISE must fall within the vertical FOV from there;
//   multirotors: the direction with its elevation clamped to 0.8 × half the vertical FOV
//     (a level camera cannot look along a steep −n̄; the thesis's UAV orients the sensor
//     freely), at δ_pose from the ISE.
// Feasibility (Definitions 2 and 4): the viewpoint's voxel is known and empty, every voxel
// within the clearance radius (ground: a cylinder from one voxel above the floor up to the
// body height; multirotor: a sphere) is empty, or unknown where the type's unknown_is_free
// allows it (multirotors by default in the ise_extractor), and a ground robot's floor under
// it is known. Merging (2.4.2): poses
// within ε whose directions differ by less than merge_angle_deg are averaged (positions,
// and directions renormalised). The thesis writes |n̄_j·n̄_k| ≈ 1; we require n̄_j·n̄_k ≈ +1,
// since two opposite views cannot be averaged into one. A merged pose that is no longer
// feasible is not merged.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/ise/ise.hpp"
#include "core/ise/ise_config.hpp"
#include "core/ise/state_grid.hpp"

namespace scancrew::ise {

struct Viewpoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // the camera, world frame
  double yaw_rad = 0;                                  // the camera looks along yaw
  RobotKind type = RobotKind::kGround;
  uint32_t types = 0;          // robot::kind_bit()s of the robot types it is feasible for
  std::vector<uint32_t> ises;  // ISEs it was generated for (indices into the ISE list)
  std::vector<uint32_t> seen;  // ISEs visible from it (gain.hpp), sorted
  Eigen::Vector3d look() const { return {std::cos(yaw_rad), std::sin(yaw_rad), 0}; }
};

// The candidate pose for one ISE and robot type, before the feasibility check; nullopt
// when the type cannot look at it (no direction; ground: no horizontal part, or the ISE
// outside the vertical FOV; multirotor: moved into its altitude band, the ISE outside the
// vertical FOV).
std::optional<Viewpoint> candidate(const Ise& ise, const RobotTypeSpec& type);

// Whether a robot of this type can stand at the position (clearance, known free space).
bool feasible(const tsdf::MapSnapshot& snap, const RobotTypeSpec& type,
              const Eigen::Vector3d& position);
// The same on the map's compact states (state_grid.hpp): what IsePipeline calls.
bool feasible(const StateGrid& states, double voxel_m, const RobotTypeSpec& type,
              const Eigen::Vector3d& position);

// Merges feasible candidates of the same type (greedy, in input order, so deterministic).
std::vector<Viewpoint> merge(const tsdf::MapSnapshot& snap, const IseConfig& config,
                             std::vector<Viewpoint> candidates);

}  // namespace scancrew::ise
