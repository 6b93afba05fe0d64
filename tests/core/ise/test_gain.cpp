// Visibility and gain (thesis 2.4.3, eq. 2.1): a viewpoint sees an ISE only along a ray
// through known empty space within the camera's range and FOV; an occupied or unknown
// voxel hides what lies behind it; g(U) = |C_U| / |C| over the union of its viewpoints'
// C_q.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/ise/clusters.hpp"
#include "core/ise/gain.hpp"
#include "tests/core/ise/voxel_scene.hpp"

namespace scancrew::ise {
namespace {

using test::VoxelScene;
using tsdf::VoxelState;

// 5 × 5 rays: the middle one runs along the optical axis, through the voxel centres of a
// camera placed at a voxel centre.
constexpr int kRows = 5, kCols = 5;

RobotTypeSpec camera() {
  RobotTypeSpec t;
  t.type = RobotKind::kMultirotor;
  t.fov_h_deg = 90;
  t.fov_v_deg = 60;
  t.min_range_m = 0.3;
  t.max_range_m = 5.0;
  return t;
}

// A known-empty corridor x ∈ [−10, 40] (voxels) with an occupied wall across it at x = 25.
// The ISE list is hand-made: A = (20,0,0) before the wall, B = (30,0,0) behind it,
// D = (−5,0,0) behind camera 1. Camera 1 at voxel 0 looks along +x; camera 2 at voxel 35
// looks along −x.
struct Corridor {
  VoxelScene scene;
  IseIndex ises;
  const Eigen::Vector3d cam1{0.05, 0.05, 0.05};
  const Eigen::Vector3d cam2{3.55, 0.05, 0.05};
  Corridor() {
    ises.emplace({20, 0, 0}, 0);
    ises.emplace({30, 0, 0}, 1);
    ises.emplace({-5, 0, 0}, 2);
    scene.fill({-10, -10, -10}, {40, 10, 10}, VoxelState::kEmpty);
    scene.fill({25, -10, -10}, {25, 10, 10}, VoxelState::kOccupied);
  }
  std::vector<uint32_t> seen(const Eigen::Vector3d& p, double yaw,
                             const RobotTypeSpec& type = camera()) const {
    return visible_ises(*scene.snapshot(), ises, type, kRows, kCols, p, yaw);
  }
};

using Ids = std::vector<uint32_t>;

TEST(GainVisibility, SeesTheIseInFrontButNotOneBehindAWallOrBehindTheCamera) {
  const Corridor c;
  EXPECT_EQ(c.seen(c.cam1, 0.0), Ids{0});
  EXPECT_EQ(c.seen(c.cam2, M_PI), Ids{1});
  // turned around, camera 1 faces D and camera 2 faces nothing but the corridor's end
  EXPECT_EQ(c.seen(c.cam1, M_PI), Ids{2});
  EXPECT_EQ(c.seen(c.cam2, 0.0), Ids{});
}

TEST(GainVisibility, UnknownVoxelOnTheRayHidesTheIse) {
  Corridor c;
  c.scene.set({10, 0, 0}, VoxelState::kUnknown);
  EXPECT_EQ(c.seen(c.cam1, 0.0), Ids{});
  c.scene.set({10, 0, 0}, VoxelState::kOccupied);
  EXPECT_EQ(c.seen(c.cam1, 0.0), Ids{});
  c.scene.set({10, 0, 0}, VoxelState::kEmpty);
  EXPECT_EQ(c.seen(c.cam1, 0.0), Ids{0});
}

TEST(GainVisibility, InOpenAirOnlyAnOccupiedVoxelHidesTheIse) {
  Corridor c;
  RobotTypeSpec open_air = camera();
  open_air.viewpoint_in_unknown = true;
  c.scene.set({10, 0, 0}, VoxelState::kUnknown);
  EXPECT_EQ(c.seen(c.cam1, 0.0, open_air), Ids{0});
  EXPECT_EQ(c.seen(c.cam1, 0.0), Ids{});  // the default still stops at unknown space
  c.scene.set({10, 0, 0}, VoxelState::kOccupied);
  EXPECT_EQ(c.seen(c.cam1, 0.0, open_air), Ids{});
  // the wall still hides B from camera 2's side
  EXPECT_EQ(c.seen(c.cam2, M_PI, open_air), Ids{1});
}

TEST(GainVisibility, RespectsTheCameraRange) {
  const Corridor c;
  RobotTypeSpec near = camera();
  near.max_range_m = 1.5;  // A is 2 m away
  EXPECT_EQ(c.seen(c.cam1, 0.0, near), Ids{});
  RobotTypeSpec far = camera();
  far.min_range_m = 2.5;  // the rays start beyond A
  EXPECT_EQ(c.seen(c.cam1, 0.0, far), Ids{});
}

TEST(GainVisibility, ViewBoundsContainEveryVoxelTheRaysReach) {
  const Corridor c;
  const double block_m = test::kVoxelM * tsdf::kBlockSide;
  BlockIndex lo, hi;
  view_bounds(camera(), c.cam1, 0.0, block_m, lo, hi);
  // 5 m ahead, ±5 m wide (90°), ±2.9 m high (60°)
  EXPECT_LE(lo.x(), 0);
  EXPECT_GE(hi.x(), static_cast<int>(std::floor(5.05 / block_m)));
  EXPECT_LE(lo.y(), static_cast<int>(std::floor(-4.95 / block_m)));
  EXPECT_GE(hi.y(), static_cast<int>(std::floor(5.05 / block_m)));
  EXPECT_LE(lo.z(), static_cast<int>(std::floor((0.05 - 5 * std::tan(M_PI / 6)) / block_m)));
  EXPECT_GE(hi.z(), static_cast<int>(std::floor((0.05 + 5 * std::tan(M_PI / 6)) / block_m)));
  EXPECT_LE(hi.x() - lo.x(), 8);  // a box, not the whole map
}

Viewpoint with_seen(const Eigen::Vector3d& p, Ids seen) {
  Viewpoint v;
  v.position = p;
  v.type = RobotKind::kMultirotor;
  v.types = robot::kind_bit(RobotKind::kMultirotor);
  v.seen = std::move(seen);
  return v;
}

TEST(GainCompute, GainIsTheShareOfAllIsesSeenByTheClusterUnion) {
  const Corridor c;
  // C = {A, B, D}: |C| = 3
  std::vector<Viewpoint> vps = {with_seen(c.cam1, c.seen(c.cam1, 0.0)),
                                with_seen(c.cam2, c.seen(c.cam2, M_PI))};
  // apart (3.5 m > d_v^max): one cluster each, 1/3 of C each
  std::vector<Cluster> clusters = cluster_viewpoints(vps, 1.0, 2.0);
  ASSERT_EQ(clusters.size(), 2u);
  compute_gains(clusters, vps, 3);
  EXPECT_EQ(clusters[0].seen, Ids{0});
  EXPECT_EQ(clusters[1].seen, Ids{1});
  EXPECT_DOUBLE_EQ(clusters[0].gain, 1.0 / 3);
  EXPECT_DOUBLE_EQ(clusters[1].gain, 1.0 / 3);

  // together, with a third viewpoint seeing A again: the union counts A once, 2/3
  vps.push_back(with_seen({1.0, 0.05, 0.05}, {0}));
  clusters = cluster_viewpoints(vps, 4.0, 4.0);
  ASSERT_EQ(clusters.size(), 1u);
  compute_gains(clusters, vps, 3);
  EXPECT_EQ(clusters[0].seen, (Ids{0, 1}));
  EXPECT_DOUBLE_EQ(clusters[0].gain, 2.0 / 3);

  // no ISE at all: gain 0, not a division by zero
  compute_gains(clusters, vps, 0);
  EXPECT_EQ(clusters[0].gain, 0.0);
}

}  // namespace
}  // namespace scancrew::ise
