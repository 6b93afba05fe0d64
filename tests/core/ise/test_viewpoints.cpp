// Viewpoints (thesis 2.4.2, Definitions 2 and 4): the candidate pose at δ_pose along the
// view direction (multirotor: elevation clamped for a level camera; ground: horizontal, at
// camera height, the ISE within the vertical FOV), yaw looking back at the ISE; feasibility
// in known free space with clearance; merging of close, near-parallel candidates.

#include <gtest/gtest.h>

#include <cmath>

#include "core/ise/viewpoints.hpp"
#include "tests/core/ise/voxel_scene.hpp"

namespace scancrew::ise {
namespace {

using test::VoxelScene;
using tsdf::VoxelState;

constexpr double kDeg = M_PI / 180;

RobotTypeSpec multirotor() {
  RobotTypeSpec t;
  t.type = RobotKind::kMultirotor;
  t.delta_pose_m = 1.5;
  t.fov_h_deg = 90;
  t.fov_v_deg = 60;
  t.clearance_m = 0.3;
  return t;
}

RobotTypeSpec ground() {
  RobotTypeSpec t;
  t.type = RobotKind::kGround;
  t.delta_pose_m = 1.5;
  t.fov_v_deg = 60;
  t.camera_height_m = 0.35;
  t.floor_z_m = 0.0;
  t.body_height_m = 0.4;
  t.clearance_m = 0.3;
  return t;
}

Ise ise_at(const Eigen::Vector3d& center, const Eigen::Vector3d& direction) {
  Ise ise;
  ise.center = center;
  ise.direction = direction.normalized();
  return ise;
}

void expect_near(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tol = 1e-9) {
  EXPECT_LT((a - b).norm(), tol) << a.transpose() << " vs " << b.transpose();
}

// --- candidate() -------------------------------------------------------------------------

TEST(ViewpointCandidate, MultirotorSitsAtDeltaPoseAlongTheDirectionLookingBack) {
  const Eigen::Vector3d c(1, 2, 3);
  auto vp = candidate(ise_at(c, {0, 1, 0}), multirotor());
  ASSERT_TRUE(vp.has_value());
  EXPECT_EQ(vp->type, RobotKind::kMultirotor);
  expect_near(vp->position, c + Eigen::Vector3d(0, 1.5, 0));
  EXPECT_NEAR(vp->yaw_rad, -M_PI / 2, 1e-12);
  expect_near(vp->look(), {0, -1, 0});

  // a moderate elevation (11.3° < 0.8 × 30°) is kept as is
  const Eigen::Vector3d d = Eigen::Vector3d(-1, 0, 0.2).normalized();
  vp = candidate(ise_at(c, d), multirotor());
  ASSERT_TRUE(vp.has_value());
  expect_near(vp->position, c + 1.5 * d);
  EXPECT_NEAR(std::cos(vp->yaw_rad), 1.0, 1e-12);  // looks along +x, back at the ISE
}

TEST(ViewpointCandidate, MultirotorClampsSteepDirectionsToTheLevelCamerasFov) {
  const Eigen::Vector3d c(-1, 0.5, 2);
  const double e = 0.8 * 30 * kDeg;
  // straight up: azimuth 0, elevation clamped to 24°
  auto vp = candidate(ise_at(c, {0, 0, 1}), multirotor());
  ASSERT_TRUE(vp.has_value());
  expect_near(vp->position, c + 1.5 * Eigen::Vector3d(std::cos(e), 0, std::sin(e)));
  EXPECT_NEAR(std::abs(vp->yaw_rad), M_PI, 1e-12);
  // steep, azimuth +y, pointing down: azimuth kept, elevation −24°
  vp = candidate(ise_at(c, {0, 1, -3}), multirotor());
  ASSERT_TRUE(vp.has_value());
  expect_near(vp->position, c + 1.5 * Eigen::Vector3d(0, std::cos(e), -std::sin(e)));
  EXPECT_NEAR(vp->yaw_rad, -M_PI / 2, 1e-12);
  EXPECT_NEAR((vp->position - c).norm(), 1.5, 1e-12);
}

TEST(ViewpointCandidate, MultirotorIsMovedIntoItsAltitudeBandWhileTheIseStaysInView) {
  RobotTypeSpec t = multirotor();
  t.min_altitude_m = 1.0;
  t.max_altitude_m = 3.0;
  // a wall's ISE 0.3 m up, looking along +y: raised from 0.3 to 1.0 m (25° down < 30°)
  auto vp = candidate(ise_at({0, 0, 0.3}, {0, 1, 0}), t);
  ASSERT_TRUE(vp.has_value());
  expect_near(vp->position, {0, 1.5, 1.0});
  EXPECT_NEAR(vp->yaw_rad, -M_PI / 2, 1e-12);
  // 3.5 m up: lowered to 3.0 m
  vp = candidate(ise_at({0, 0, 3.5}, {1, 0, 0}), t);
  ASSERT_TRUE(vp.has_value());
  expect_near(vp->position, {1.5, 0, 3.0});
  // on the floor, 0.05 m up: 1.0 m would see it 32° down, outside the ±30° FOV
  EXPECT_FALSE(candidate(ise_at({0, 0, 0.05}, {0, 1, 0}), t).has_value());
  // within the band: as without it
  vp = candidate(ise_at({0, 0, 2}, {0, 1, 0}), t);
  ASSERT_TRUE(vp.has_value());
  expect_near(vp->position, {0, 1.5, 2});
}

TEST(ViewpointCandidate, GroundRobotStaysAtCameraHeightAlongTheHorizontalPart) {
  const Eigen::Vector3d c(1, 2, 0.5);
  auto vp = candidate(ise_at(c, {3, 4, 5}), ground());
  ASSERT_TRUE(vp.has_value());
  EXPECT_EQ(vp->type, RobotKind::kGround);
  expect_near(vp->position, {1 + 1.5 * 0.6, 2 + 1.5 * 0.8, 0.35});
  EXPECT_NEAR(vp->yaw_rad, std::atan2(-0.8, -0.6), 1e-12);
}

TEST(ViewpointCandidate, GroundRobotRejectsIsesOutsideItsVerticalFov) {
  // camera at 0.35 m, 1.5 m away, half vertical FOV 30°
  EXPECT_TRUE(candidate(ise_at({0, 0, 1.1}, {1, 0, 0}), ground()).has_value());    // 26.6°
  EXPECT_FALSE(candidate(ise_at({0, 0, 2.0}, {1, 0, 0}), ground()).has_value());   // 47.7°
  EXPECT_FALSE(candidate(ise_at({0, 0, -0.6}, {1, 0, 0}), ground()).has_value());  // −32.3°
  // no horizontal part to stand along
  EXPECT_FALSE(candidate(ise_at({0, 0, 0.35}, {0, 0, 1}), ground()).has_value());
  // no direction at all: neither type
  Ise none;
  none.center = {0, 0, 0.35};
  EXPECT_FALSE(candidate(none, ground()).has_value());
  EXPECT_FALSE(candidate(none, multirotor()).has_value());
}

// --- feasible() --------------------------------------------------------------------------

// Known empty space 2 m across around the origin's voxel.
void build_free_space(VoxelScene& scene) {
  scene.fill({-10, -10, -10}, {10, 10, 10}, VoxelState::kEmpty);
}
const Eigen::Vector3d kAtVoxel0(0.05, 0.05, 0.05);  // centre of voxel (0, 0, 0)

TEST(ViewpointFeasible, MultirotorNeedsKnownEmptySpaceWithinItsClearance) {
  VoxelScene scene;
  build_free_space(scene);
  EXPECT_TRUE(feasible(*scene.snapshot(), multirotor(), kAtVoxel0));
  // 0.4 m away (the voxel's nearest point 0.35 m): outside the 0.3 m clearance
  scene.set({4, 0, 0}, VoxelState::kOccupied);
  scene.set({0, -4, 0}, VoxelState::kUnknown);
  EXPECT_TRUE(feasible(*scene.snapshot(), multirotor(), kAtVoxel0));
  // 0.3 m away, on a diagonal: inside
  scene.set({2, 2, 1}, VoxelState::kOccupied);
  EXPECT_FALSE(feasible(*scene.snapshot(), multirotor(), kAtVoxel0));
  scene.set({2, 2, 1}, VoxelState::kEmpty);
  scene.set({0, 0, -3}, VoxelState::kOccupied);
  EXPECT_FALSE(feasible(*scene.snapshot(), multirotor(), kAtVoxel0));
  scene.set({0, 0, -3}, VoxelState::kEmpty);
  // unknown within the clearance: not known to be free
  scene.set({0, 1, 1}, VoxelState::kUnknown);
  EXPECT_FALSE(feasible(*scene.snapshot(), multirotor(), kAtVoxel0));
  // unless the type takes unknown space as free; an obstacle still is not
  RobotTypeSpec optimistic = multirotor();
  optimistic.unknown_is_free = true;
  EXPECT_TRUE(feasible(*scene.snapshot(), optimistic, kAtVoxel0));
  scene.set({1, 1, 0}, VoxelState::kOccupied);
  EXPECT_FALSE(feasible(*scene.snapshot(), optimistic, kAtVoxel0));
  scene.set({1, 1, 0}, VoxelState::kEmpty);
  scene.set({0, 1, 1}, VoxelState::kEmpty);
  EXPECT_TRUE(feasible(*scene.snapshot(), multirotor(), kAtVoxel0));
  // never observed space (the viewpoint's own voxel unknown: not even for the optimist),
  // and inside an obstacle
  EXPECT_FALSE(feasible(*scene.snapshot(), multirotor(), {5, 5, 5}));
  EXPECT_FALSE(feasible(*scene.snapshot(), optimistic, {5, 5, 5}));
  scene.set({0, 0, 0}, VoxelState::kOccupied);
  EXPECT_FALSE(feasible(*scene.snapshot(), multirotor(), kAtVoxel0));
}

TEST(ViewpointFeasible, InOpenAirTheViewpointsOwnVoxelMayBeUnknownButNotOccupied) {
  VoxelScene scene;
  build_free_space(scene);
  RobotTypeSpec open_air = multirotor();
  open_air.unknown_is_free = true;
  open_air.viewpoint_in_unknown = true;
  scene.set({0, 0, 0}, VoxelState::kUnknown);
  EXPECT_TRUE(feasible(*scene.snapshot(), open_air, kAtVoxel0));
  RobotTypeSpec optimistic = multirotor();
  optimistic.unknown_is_free = true;
  EXPECT_FALSE(feasible(*scene.snapshot(), optimistic, kAtVoxel0));
  // never observed space, far from anything
  EXPECT_TRUE(feasible(*scene.snapshot(), open_air, {5, 5, 5}));
  // an obstacle in the clearance ball or at the viewpoint still makes it infeasible
  scene.set({1, 1, 0}, VoxelState::kOccupied);
  EXPECT_FALSE(feasible(*scene.snapshot(), open_air, kAtVoxel0));
  scene.set({1, 1, 0}, VoxelState::kEmpty);
  scene.set({0, 0, 0}, VoxelState::kOccupied);
  EXPECT_FALSE(feasible(*scene.snapshot(), open_air, kAtVoxel0));
}

// A floor (occupied layer z = −1, the surface at z = 0) under known empty space.
void build_floor(VoxelScene& scene) {
  scene.fill({-10, -10, -1}, {10, 10, -1}, VoxelState::kOccupied);
  scene.fill({-10, -10, 0}, {10, 10, 10}, VoxelState::kEmpty);
}
const Eigen::Vector3d kGroundCam(0.05, 0.05, 0.35);

TEST(ViewpointFeasible, GroundRobotNeedsAKnownFloorAndAFreeBodyCylinder) {
  VoxelScene scene;
  build_floor(scene);
  EXPECT_TRUE(feasible(*scene.snapshot(), ground(), kGroundCam));
  // obstacles above the body's height or beyond the footprint do not matter
  scene.set({0, 0, 6}, VoxelState::kOccupied);
  scene.set({4, 0, 2}, VoxelState::kOccupied);
  EXPECT_TRUE(feasible(*scene.snapshot(), ground(), kGroundCam));
  // within the footprint, at body height
  scene.set({2, 0, 3}, VoxelState::kOccupied);
  EXPECT_FALSE(feasible(*scene.snapshot(), ground(), kGroundCam));
  scene.set({2, 0, 3}, VoxelState::kEmpty);
  scene.set({0, -1, 1}, VoxelState::kUnknown);
  EXPECT_FALSE(feasible(*scene.snapshot(), ground(), kGroundCam));
  scene.set({0, -1, 1}, VoxelState::kEmpty);
  ASSERT_TRUE(feasible(*scene.snapshot(), ground(), kGroundCam));
  // the floor voxel unknown under known empty air: a floor seen at a grazing angle
  scene.set({0, 0, -1}, VoxelState::kUnknown);
  EXPECT_TRUE(feasible(*scene.snapshot(), ground(), kGroundCam));
  // ... but not under unknown air: nothing seen there
  scene.set({0, 0, 0}, VoxelState::kUnknown);
  EXPECT_FALSE(feasible(*scene.snapshot(), ground(), kGroundCam));
  scene.set({0, 0, 0}, VoxelState::kEmpty);
  // known but empty (a hole): no floor to stand on
  scene.set({0, 0, -1}, VoxelState::kEmpty);
  EXPECT_FALSE(feasible(*scene.snapshot(), ground(), kGroundCam));
}

TEST(ViewpointFeasible, GroundRobotWithoutAnyFloorIsInfeasible) {
  VoxelScene scene;
  build_free_space(scene);  // free space all the way down: no floor anywhere
  EXPECT_FALSE(feasible(*scene.snapshot(), ground(), kGroundCam));
  EXPECT_TRUE(feasible(*scene.snapshot(), multirotor(), kGroundCam));
}

// --- merge() -----------------------------------------------------------------------------

IseConfig merge_config() {
  IseConfig c;
  c.robot_types = {multirotor(), ground()};
  c.merge_distance_m = 0.5;
  c.merge_angle_deg = 20;
  return c;
}

Viewpoint vp(const Eigen::Vector3d& p, double yaw, uint32_t ise,
             RobotKind type = RobotKind::kMultirotor) {
  Viewpoint v;
  v.position = p;
  v.yaw_rad = yaw;
  v.type = type;
  v.ises = {ise};
  return v;
}

TEST(ViewpointMerge, CloseNearParallelCandidatesMergeIntoTheirAverage) {
  VoxelScene scene;
  build_free_space(scene);
  const auto snap = scene.snapshot();
  const Eigen::Vector3d a(0.0, 0.0, 0.0), b(0.3, 0.1, 0.0);  // 0.32 m, 11.5° apart
  const auto out = merge(*snap, merge_config(), {vp(a, 0.0, 5), vp(b, 0.2, 2)});
  ASSERT_EQ(out.size(), 1u);
  expect_near(out[0].position, (a + b) / 2);
  EXPECT_NEAR(out[0].yaw_rad, 0.1, 1e-12);  // the mean of two unit look vectors
  EXPECT_EQ(out[0].ises, (std::vector<uint32_t>{2, 5}));
}

TEST(ViewpointMerge, FarApartOrAngledOrDifferentTypesStaySeparate) {
  VoxelScene scene;
  build_free_space(scene);
  const auto snap = scene.snapshot();
  const Eigen::Vector3d a(0.0, 0.0, 0.0);
  const IseConfig config = merge_config();
  // 0.6 m > ε = 0.5 m
  auto out = merge(*snap, config, {vp(a, 0.0, 0), vp(a + Eigen::Vector3d(0.6, 0, 0), 0.0, 1)});
  ASSERT_EQ(out.size(), 2u);
  expect_near(out[1].position, {0.6, 0, 0});
  // 0.1 m apart but 28.6° > 20°
  out = merge(*snap, config, {vp(a, 0.0, 0), vp(a + Eigen::Vector3d(0.1, 0, 0), 0.5, 1)});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].yaw_rad, 0.0);
  EXPECT_EQ(out[1].yaw_rad, 0.5);
  // near-opposite views are not averaged (n̄_j·n̄_k ≈ −1, so |n̄_j·n̄_k| ≈ 1)
  out = merge(*snap, config, {vp(a, 0.0, 0), vp(a, M_PI - 0.1, 1)});
  EXPECT_EQ(out.size(), 2u);
  // the same pose for different robot types
  out = merge(*snap, config, {vp(a, 0.0, 0), vp(a, 0.0, 1, RobotKind::kGround)});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].ises, std::vector<uint32_t>{0});
  EXPECT_EQ(out[1].ises, std::vector<uint32_t>{1});
}

TEST(ViewpointMerge, MergedPoseThatIsNotFeasibleIsNotMerged) {
  VoxelScene scene;
  build_free_space(scene);
  scene.set({0, 0, 3}, VoxelState::kOccupied);  // 0.3 m above the midpoint's voxel
  const auto snap = scene.snapshot();
  IseConfig config = merge_config();
  config.merge_distance_m = 1.0;
  const Eigen::Vector3d a(-0.35, 0.05, 0.05), b(0.45, 0.05, 0.05);  // voxels x = −4, 4
  ASSERT_TRUE(feasible(*snap, multirotor(), a));
  ASSERT_TRUE(feasible(*snap, multirotor(), b));
  ASSERT_FALSE(feasible(*snap, multirotor(), (a + b) / 2));
  const auto out = merge(*snap, config, {vp(a, 0.0, 0), vp(b, 0.0, 1)});
  ASSERT_EQ(out.size(), 2u);
  expect_near(out[0].position, a);
  expect_near(out[1].position, b);
}

}  // namespace
}  // namespace scancrew::ise
