// The compact voxel states (state_grid.hpp) read as the TSDF does: every voxel's state, a
// refresh after a map update equal to a rebuild, and visibility and feasibility on the
// compact states equal to the same on the snapshot.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/ise/gain.hpp"
#include "core/ise/state_grid.hpp"
#include "core/ise/viewpoints.hpp"
#include "tests/core/ise/voxel_scene.hpp"

namespace scancrew::ise {
namespace {

using test::VoxelScene;
using tsdf::VoxelState;

// Random states over a box across the origin (negative block coordinates included), with
// holes of never-written voxels; a fixed seed.
void random_scene(VoxelScene& scene, std::mt19937& rng, int half) {
  std::uniform_int_distribution<int> pick(0, 9);
  for (int z = -half; z < half; ++z)
    for (int y = -half; y < half; ++y)
      for (int x = -half; x < half; ++x) {
        const int p = pick(rng);
        if (p == 0) continue;  // never written
        scene.set({x, y, z}, p == 1   ? VoxelState::kOccupied
                             : p == 2 ? VoxelState::kUnknown
                                      : VoxelState::kEmpty);
      }
}

void expect_same_states(const tsdf::MapSnapshot& snap, const StateGrid& grid, int half) {
  StateGrid::Reader reader(grid);
  int mismatches = 0;
  for (int z = -half - 8; z < half + 8; ++z)
    for (int y = -half - 8; y < half + 8; ++y)
      for (int x = -half - 8; x < half + 8; ++x)
        if (reader.state({x, y, z}) != snap.state({x, y, z})) ++mismatches;
  EXPECT_EQ(mismatches, 0);
}

TEST(StateGrid, ReadsEveryVoxelsStateAsTheSnapshotDoes) {
  VoxelScene scene;
  std::mt19937 rng(7);
  random_scene(scene, rng, 12);
  const auto snap = scene.snapshot();
  const StateGrid grid(*snap);
  EXPECT_EQ(grid.block_count(), snap->block_count());
  expect_same_states(*snap, grid, 12);
}

TEST(StateGrid, RefreshOfTheChangedBlocksEqualsARebuild) {
  VoxelScene scene;
  std::mt19937 rng(11);
  random_scene(scene, rng, 12);
  const auto before = scene.snapshot();
  StateGrid grid(*before);
  scene.next_update();
  scene.fill({-3, -3, -3}, {3, 3, 3}, VoxelState::kOccupied);
  scene.set({10, -11, 5}, VoxelState::kUnknown);
  const BlockIndex gone(-2, 1, 0);
  scene.erase_block(gone);
  const auto after = scene.snapshot();
  std::vector<BlockIndex> changed = after->changed_since(before->sequence());
  changed.push_back(gone);
  grid.refresh(*after, changed);
  EXPECT_EQ(grid.block(gone), nullptr);
  EXPECT_EQ(grid.block_count(), after->block_count());
  expect_same_states(*after, grid, 12);
}

TEST(StateGrid, VisibilityAndFeasibilityEqualTheSnapshots) {
  VoxelScene scene;
  std::mt19937 rng(3);
  // mostly empty space, so that rays run long, with obstacles and unknown voxels
  std::uniform_int_distribution<int> pick(0, 39);
  for (int z = -20; z < 20; ++z)
    for (int y = -20; y < 20; ++y)
      for (int x = -20; x < 20; ++x) {
        const int p = pick(rng);
        scene.set({x, y, z}, p == 0   ? VoxelState::kOccupied
                             : p == 1 ? VoxelState::kUnknown
                                      : VoxelState::kEmpty);
      }
  const auto snap = scene.snapshot();
  const StateGrid grid(*snap);
  IseIndex ises;
  uint32_t id = 0;
  for (int z = -20; z < 20; z += 3)
    for (int y = -20; y < 20; y += 3)
      for (int x = -20; x < 20; x += 3) ises.emplace({x, y, z}, id++);
  RobotTypeSpec type;
  type.type = RobotKind::kMultirotor;
  type.fov_h_deg = 90;
  type.fov_v_deg = 60;
  type.min_range_m = 0.2;
  type.max_range_m = 1.8;
  type.clearance_m = 0.2;
  std::uniform_real_distribution<double> coord(-1.5, 1.5), yaw(-M_PI, M_PI);
  size_t seen = 0, feasible_count = 0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(coord(rng), coord(rng), coord(rng));
    const double a = yaw(rng);
    const auto on_snap = visible_ises(*snap, ises, type, 9, 11, p, a);
    EXPECT_EQ(visible_ises(grid, snap->voxel_m(), ises, type, 9, 11, p, a), on_snap);
    seen += on_snap.size();
    for (const bool in_unknown : {false, true}) {
      type.viewpoint_in_unknown = in_unknown;
      type.unknown_is_free = in_unknown;
      const bool f = feasible(*snap, type, p);
      EXPECT_EQ(feasible(grid, snap->voxel_m(), type, p), f);
      feasible_count += f ? 1 : 0;
    }
    type.viewpoint_in_unknown = false;
    type.unknown_is_free = false;
  }
  // the comparison covered both outcomes
  EXPECT_GT(seen, 200u);
  EXPECT_GT(feasible_count, 0u);
  EXPECT_LT(feasible_count, 400u);
}

}  // namespace
}  // namespace scancrew::ise
