// Guided sampling for ground robots (core/motion/guide_path.hpp): the 2D grid
// search through a 1 m corridor, its failures, unknown space by config, and the planner
// that seeds LazyPRM*'s roadmap with it.

#include <gtest/gtest.h>

#include <cmath>

#include "core/motion/guide_path.hpp"
#include "core/motion/motion_planner.hpp"
#include "tests/core/motion/box_world.hpp"

namespace scancrew::motion {
namespace {

using test::BoxWorld;
using V3 = Eigen::Vector3d;

constexpr int64_t kStampNs = 1'000'000'000;

// 10 × 6 m observed at 0.1 m, a floor, and two 1.2 m high walls from x = 3 to 7 that leave
// one corridor, y in [2.5, 3.5], between the two halves of the room.
BoxWorld corridor_world() {
  BoxWorld w(0.1, Eigen::AlignedBox3d(V3(0, 0, -0.2), V3(10, 6, 1.2)));
  w.add_box(V3(-1, -1, -0.2), V3(11, 7, 0));  // floor
  w.add_box(V3(3, -1, 0), V3(7, 2.5, 1.2));
  w.add_box(V3(3, 3.5, 0), V3(7, 7, 1.2));
  return w;
}

// The planner's body (thesis ellipsoid + 0.1 m margin) at its mid-height.
GuideConfig guide_config(bool unknown_is_occupied = true) {
  GuideConfig g;
  g.z_lo_m = g.z_hi_m = 0.5;
  g.clearance_m = 0.35;
  g.spacing_m = 0.65;
  g.unknown_is_occupied = unknown_is_occupied;
  return g;
}

// the grid's box: the observed room and 2–4 m of unknown space around it
Eigen::AlignedBox2d grid_box() {
  return {Eigen::Vector2d(-2, -2), Eigen::Vector2d(14, 8)};
}

TEST(GuideGrid, PosesRunThroughTheCorridorAlongIt) {
  BoxWorld world = corridor_world();
  const GuideGrid grid(*world.write(), grid_box(), guide_config());
  const std::vector<GuidePose> poses = grid.search({1, 1}, {9, 5});
  ASSERT_GE(poses.size(), 8u);  // ≥ 8 m of grid path, a pose every 0.65 m
  size_t inside = 0;
  for (const GuidePose& p : poses) {
    if (p.x < 3 || p.x > 7) continue;
    ++inside;
    EXPECT_GT(p.y, 2.5 + 0.25) << "at x = " << p.x;  // the clearance less half a diagonal
    EXPECT_LT(p.y, 3.5 - 0.25) << "at x = " << p.x;
    // along it, once past the entrance (the yaw looks half the spacing each way)
    if (p.x > 3.7 && p.x < 6.3)
      EXPECT_LT(std::abs(std::sin(p.yaw)), 0.2) << "yaw " << p.yaw << " at x = " << p.x;
  }
  EXPECT_GE(inside, 5u);  // the corridor is 4 m long
  // consecutive poses about the spacing apart
  for (size_t i = 1; i < poses.size(); ++i) {
    const double d = std::hypot(poses[i].x - poses[i - 1].x, poses[i].y - poses[i - 1].y);
    EXPECT_GT(d, 0.4);
    EXPECT_LT(d, 0.9);
  }
}

TEST(GuideGrid, AClosedCorridorGivesNoPoses) {
  BoxWorld world = corridor_world();
  world.add_box(V3(4.9, 2.4, 0), V3(5.1, 3.6, 1.2));
  world.write();
  const GuideGrid grid(*world.write(), grid_box(), guide_config());
  EXPECT_TRUE(grid.search({1, 1}, {9, 5}).empty());
  // the same side of the walls is still connected
  EXPECT_FALSE(grid.search({1, 1}, {2, 5}).empty());
}

TEST(GuideGrid, UnknownSpaceBlocksOnlyWhenUnknownIsOccupied) {
  BoxWorld world = corridor_world();
  const auto map = world.write();
  // the goal lies beyond the observed region (x > 10): unknown all the way from x = 10
  EXPECT_TRUE(GuideGrid(*map, grid_box(), guide_config(true)).search({1, 3}, {12, 3}).empty());
  EXPECT_FALSE(GuideGrid(*map, grid_box(), guide_config(false)).search({1, 3}, {12, 3}).empty());
}

TEST(GuideGrid, EndsOutsideTheBoxOrNotFiniteGiveNoPoses) {
  BoxWorld world = corridor_world();
  const GuideGrid grid(*world.write(), grid_box(), guide_config());
  EXPECT_TRUE(grid.search({1, 1}, {20, 5}).empty());
  EXPECT_TRUE(grid.search({std::nan(""), 1}, {9, 5}).empty());
  EXPECT_GT(grid.cells(), 0u);
}

msg::Waypoint pose(double x, double y, double yaw = 0) {
  msg::Waypoint w;
  w.position = {x, y, 0};
  w.yaw_rad = yaw;
  return w;
}

PlannerConfig ground_config(bool guide) {
  PlannerConfig c;
  c.robot_kind = RobotKind::kGround;
  c.seed = 1;
  c.collision_check_step_m = 0.05;
  c.guide_grid = guide;
  return c;
}

TEST(MotionPlanner, GuidedSamplingThreadsTheCorridorWithFewVertices) {
  BoxWorld world = corridor_world();
  const PlannerConfig c = ground_config(true);
  auto planner = MotionPlanner::create(c);
  ASSERT_TRUE(planner.has_value()) << planner.error();
  planner->update_map(world.write(), kStampNs);
  // the start faces across the corridor: the path turns the ellipse before it enters
  const PlanResult r = planner->plan({pose(1, 1, M_PI / 2), pose(9, 5, M_PI), kStampNs});
  ASSERT_EQ(r.status, PlanStatus::kOk) << r.message;
  EXPECT_GT(r.stats.guide_milestones, 5u);
  EXPECT_LT(r.stats.roadmap_vertices, 200u);
  PlannerConfig bare = c;
  bare.body_margin_m = 0;
  const PathCheck check = world.truth().check_path(bare, body_of(bare), r.path, 0.02);
  EXPECT_GT(check.samples, 100u);
  EXPECT_EQ(check.colliding, 0u);
  // the ends are the caller's poses
  EXPECT_DOUBLE_EQ(r.path.front().yaw_rad, M_PI / 2);
  EXPECT_DOUBLE_EQ(r.path.back().yaw_rad, M_PI);
}

TEST(MotionPlanner, WithoutTheGuideNoGuideMilestones) {
  BoxWorld world = corridor_world();
  auto planner = MotionPlanner::create(ground_config(false));
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanResult r = planner->plan({pose(1, 1), pose(9, 5), kStampNs});
  EXPECT_EQ(r.stats.guide_milestones, 0u);
  if (r.status == PlanStatus::kOk) EXPECT_GT(r.path.size(), 2u);
}

}  // namespace
}  // namespace scancrew::motion
