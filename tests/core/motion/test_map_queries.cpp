// The checks on a real tsdf::MapSnapshot through map_queries.hpp: occupancy for
// ObstacleCheck, free space for the traffic policy's aside point.

#include <gtest/gtest.h>

#include "core/motion/map_queries.hpp"
#include "core/motion/obstacle_check.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::motion {
namespace {

constexpr double kVoxelM = 0.1;

// a 4 x 2 x 1 m observed region of free voxels with an occupied pillar at x = 2 m, and the
// floor below z = 0 occupied
std::shared_ptr<const tsdf::MapSnapshot> pillar_map() {
  tsdf::TsdfConfig c;
  c.voxel_m = kVoxelM;
  c.truncation_m = 3 * kVoxelM;
  c.w_th = 0.5;
  tsdf::TsdfMap map(c);
  const uint64_t seq = map.begin_update();
  for (int z = -1; z < 10; ++z)
    for (int y = -10; y < 10; ++y)
      for (int x = 0; x < 40; ++x) {
        const tsdf::VoxelIndex v(x, y, z);
        const bool occupied = z < 0 || (x >= 20 && x < 22 && y >= -1 && y < 1);
        tsdf::Block& b = map.touch(tsdf::block_of(v));
        b.modified = seq;
        const Eigen::Vector3i l = tsdf::local_of(v);
        b.at(l.x(), l.y(), l.z()) = occupied ? tsdf::Voxel{-0.05f, 1.0f} : tsdf::Voxel{0.1f, 1.0f};
      }
  return map.snapshot();
}

TEST(MapQueries, ObstacleCheckOnASnapshotSeesThePillarNotTheFloor) {
  const auto map = pillar_map();
  const OccupancyQuery occupied = occupancy_query(map);
  const ObstacleCheckConfig ground = ObstacleCheckConfig::for_kind(RobotKind::kGround);
  EXPECT_FALSE(obstacle_check({1.0, 0.0, 0.0}, 0.0, map->voxel_m(), occupied, ground).stop());
  const ObstacleCheckResult r =
      obstacle_check({1.6, 0.0, 0.0}, 0.0, map->voxel_m(), occupied, ground);
  EXPECT_TRUE(r.stop());
  EXPECT_NEAR(r.nearest_occupied.x(), 2.05, 1e-9);
  EXPECT_FALSE(occupancy_query(nullptr));
}

TEST(MapQueries, FreeSpaceNeedsRoomForTheBodyAndKnownSpace) {
  const auto map = pillar_map();
  const FreeSpaceQuery free = free_space_query(map, {});
  EXPECT_TRUE(free({1.0, 0.0, 0.0}));
  EXPECT_FALSE(free({1.8, 0.0, 0.0})) << "within 0.3 m of the pillar";
  EXPECT_TRUE(free({2.1, 0.6, 0.0})) << "beside it";
  EXPECT_FALSE(free({6.0, 0.0, 0.0})) << "unknown space";
  FreeSpaceSpec optimistic;
  optimistic.unknown_is_free = true;
  EXPECT_TRUE(free_space_query(map, optimistic)({6.0, 0.0, 0.0}));
}

}  // namespace
}  // namespace scancrew::motion
