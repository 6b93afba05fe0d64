// CollisionMap (core/motion/collision_map.hpp): the body against the octree of a
// hand-built map, unknown space by config, and the incremental update matching a rebuild.

#include <gtest/gtest.h>

#include <random>

#include "core/motion/collision_map.hpp"
#include "tests/core/motion/box_world.hpp"

namespace scancrew::motion {
namespace {

using test::BoxWorld;
using V3 = Eigen::Vector3d;

Eigen::Isometry3d at(double x, double y, double z, double yaw = 0) {
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  T_world_body.translation() = V3(x, y, z);
  T_world_body.linear() = Eigen::AngleAxisd(yaw, V3::UnitZ()).toRotationMatrix();
  return T_world_body;
}

robot::BodyModel ellipse() {
  robot::BodyModel b;
  b.safety_radii_m = V3(0.55, 0.25, 0.25);
  return b;
}

TEST(CollisionMap, EllipsoidTouchesTheBoxAlongItsLongAxisOnly) {
  BoxWorld world(0.1, Eigen::AlignedBox3d(V3(0, 0, 0), V3(4, 4, 1)));
  world.add_box(V3(2, 0, 0), V3(2.2, 4, 1));  // a wall at x in [2, 2.2]
  CollisionMap map(ellipse(), /*unknown_is_occupied=*/true);
  EXPECT_FALSE(map.collides(at(1, 2, 0.5)));  // no map yet
  const CollisionMapUpdate u = map.update(world.write());
  EXPECT_TRUE(u.rebuilt);
  EXPECT_GT(map.leaf_count(), 0u);
  // 0.6 m from the wall: facing it, the 0.55 m semi-axis is clear; 0.5 m: it touches
  EXPECT_FALSE(map.collides(at(1.4, 2, 0.5)));
  EXPECT_TRUE(map.collides(at(1.5, 2, 0.5)));
  // turned 90°, 0.3 m from the wall is clear (0.25 m semi-axis)
  EXPECT_FALSE(map.collides(at(1.7, 2, 0.5, M_PI / 2)));
  EXPECT_TRUE(map.collides(at(1.7, 2, 0.5)));
}

TEST(CollisionMap, UnknownSpaceCollidesOnlyWhenConfigured) {
  BoxWorld world(0.1, Eigen::AlignedBox3d(V3(0, 0, 0), V3(4, 4, 1)));
  CollisionMap strict(ellipse(), true), lenient(ellipse(), false);
  const auto snap = world.write();
  strict.update(snap);
  lenient.update(snap);
  // near the region's edge (x = 4) and beyond it: unknown, in observed blocks or not
  EXPECT_TRUE(strict.collides(at(3.6, 2, 0.5)));
  EXPECT_FALSE(lenient.collides(at(3.6, 2, 0.5)));
  EXPECT_TRUE(strict.collides(at(20, 2, 0.5)));  // no block there at all
  EXPECT_FALSE(lenient.collides(at(20, 2, 0.5)));
  EXPECT_FALSE(strict.collides(at(2, 2, 0.5)));
  EXPECT_EQ(strict.state_at(V3(20, 2, 0.5)), tsdf::VoxelState::kUnknown);
  EXPECT_EQ(strict.state_at(V3(2, 2, 0.5)), tsdf::VoxelState::kEmpty);
}

TEST(CollisionMap, IncrementalUpdateRewritesTheChangedBlocksAndMatchesARebuild) {
  BoxWorld world(0.1, Eigen::AlignedBox3d(V3(0, 0, 0), V3(6, 6, 1)));
  world.add_box(V3(1, 1, 0), V3(1.5, 5, 1));
  CollisionMap incremental(ellipse(), true);
  incremental.update(world.write());
  world.add_box(V3(3.95, 2.95, 0), V3(4.15, 3.15, 1));  // a post
  const auto snap = world.write();
  const CollisionMapUpdate u = incremental.update(snap);
  EXPECT_FALSE(u.rebuilt);
  EXPECT_GE(u.changed.size(), 1u);
  EXPECT_LE(u.changed.size(), 8u);  // the post's blocks (0.8 m blocks), not the 8 × 8 × 2 map
  CollisionMap fresh(ellipse(), true);
  fresh.update(snap);
  EXPECT_TRUE(incremental.collides(at(4.05, 3.05, 0.5)));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x(0, 6), yaw(-M_PI, M_PI);
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Isometry3d T_world_body = at(x(rng), x(rng), 0.5, yaw(rng));
    ASSERT_EQ(incremental.collides(T_world_body), fresh.collides(T_world_body))
        << T_world_body.translation().transpose();
  }
}

}  // namespace
}  // namespace scancrew::motion
