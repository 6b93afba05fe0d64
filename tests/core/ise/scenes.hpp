#pragma once

// The scenes the pipeline tests share, with their ISEs worked out by hand.
//
// Room: known empty space, voxels [−28, 28]³, with an occupied wall at x = −1 (y, z in
// [−5, 5]) that has a hole: (−1, 0, 0) unknown. The hole's two face neighbours off the wall,
// (0, 0, 0) and (−2, 0, 0), are the room's only ISEs (the room's outer faces border unknown
// space but have no occupied voxel near); their directions are +x and −x, their multirotor
// viewpoints at δ_pose = 2 m, (2.05, 0.05, 0.05) and (−2.15, 0.05, 0.05), in free space.
//
// Pocket: a solid occupied cube, voxels [40, 64]³, enclosing an empty 3³ pocket [51, 53]³
// whose centre (52, 52, 52) is unknown. The centre's six face neighbours are ISEs (an
// unknown 6-neighbour, the cube's wall as 18-neighbour), looking towards the centre; each
// one's viewpoint, 2 m on, lands in unknown space beyond the cube, and nothing outside sees
// into the pocket: C_rem.

#include <set>

#include "core/ise/ise_config.hpp"
#include "tests/core/ise/voxel_scene.hpp"

namespace scancrew::ise::test {

inline void build_room(VoxelScene& scene) {
  scene.fill({-28, -28, -28}, {28, 28, 28}, VoxelState::kEmpty);
  scene.fill({-1, -5, -5}, {-1, 5, 5}, VoxelState::kOccupied);
  scene.set({-1, 0, 0}, VoxelState::kUnknown);
}

inline void build_pocket(VoxelScene& scene) {
  scene.fill({40, 40, 40}, {64, 64, 64}, VoxelState::kOccupied);
  scene.fill({51, 51, 51}, {53, 53, 53}, VoxelState::kEmpty);
  scene.set({52, 52, 52}, VoxelState::kUnknown);
}

inline const std::set<Key> kRoomIses = {{0, 0, 0}, {-2, 0, 0}};
inline const std::set<Key> kPocketIses = {{51, 52, 52}, {53, 52, 52}, {52, 51, 52},
                                          {52, 53, 52}, {52, 52, 51}, {52, 52, 53}};

// One multirotor type; an odd number of gain rays, so the middle ray runs along the
// optical axis and sees the ISE its viewpoint was made for.
inline IseConfig pipeline_config() {
  RobotTypeSpec air;
  air.type = RobotKind::kMultirotor;
  air.delta_pose_m = 2.0;
  air.fov_h_deg = 90;
  air.fov_v_deg = 60;
  air.min_range_m = 0.3;
  air.max_range_m = 5.0;
  air.clearance_m = 0.3;
  IseConfig c;
  c.robot_types = {air};
  c.merge_distance_m = 0.5;
  c.merge_angle_deg = 20;
  c.d_v_m = 2.0;
  c.d_v_max_m = 5.0;
  c.gain_rows = 5;
  c.gain_cols = 7;
  c.completion_updates = 2;
  return c;
}

}  // namespace scancrew::ise::test
