// The low-level planner's core (core/motion/motion_planner.hpp) on hand-built maps:
// paths collision-free against the true boxes, a wall added in a later snapshot avoided by
// the reused roadmap, and every failing status.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "core/motion/motion_planner.hpp"
#include "executors/params.hpp"
#include "tests/core/motion/box_world.hpp"

namespace scancrew::motion {
namespace {

using test::BoxWorld;
using V3 = Eigen::Vector3d;

constexpr int64_t kStampNs = 1'000'000'000;

msg::Waypoint pose(double x, double y, double z = 0, double yaw = 0) {
  msg::Waypoint w;
  w.position = {x, y, z};
  w.yaw_rad = yaw;
  return w;
}

PlanRequest request(const msg::Waypoint& start, const msg::Waypoint& goal) {
  return {start, goal, kStampNs};
}

PlannerConfig ground_config() {
  PlannerConfig c;
  c.robot_kind = RobotKind::kGround;
  c.seed = 1;
  c.collision_check_step_m = 0.05;
  return c;
}

// The thesis's body, without the margin: what must not touch the true obstacles.
robot::BodyModel true_body(PlannerConfig c) {
  c.body_margin_m = 0;
  return body_of(c);
}

// 10 × 6 m observed at 0.1 m, a floor, and a wall across x = 5 from y = 1.5 to 4.5: two
// 1.5 m gaps, at y < 1.5 and y > 4.5 (beyond the region, y < 0 and y > 6, is unknown).
BoxWorld ground_world() {
  BoxWorld w(0.1, Eigen::AlignedBox3d(V3(0, 0, -0.2), V3(10, 6, 1.2)));
  w.add_box(V3(-1, -1, -0.2), V3(11, 7, 0));  // floor
  w.add_box(V3(4.8, 1.5, 0), V3(5.2, 4.5, 1.2));
  return w;
}

// Where the path crosses x = 5 (the wall's plane); NaN if it does not.
double crossing_y(const std::vector<msg::Waypoint>& path) {
  for (size_t i = 1; i < path.size(); ++i) {
    const double x0 = path[i - 1].position.x, x1 = path[i].position.x;
    if ((x0 - 5) * (x1 - 5) <= 0 && x0 != x1) {
      const double t = (5 - x0) / (x1 - x0);
      return path[i - 1].position.y + t * (path[i].position.y - path[i - 1].position.y);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

void expect_collision_free(const ObstacleGeometry& truth, const PlannerConfig& c,
                           const PlanResult& r) {
  const PathCheck check = truth.check_path(c, true_body(c), r.path, 0.02);
  EXPECT_GT(check.samples, 10u);
  EXPECT_EQ(check.colliding, 0u) << "first at (" << check.first_colliding.position.x << ", "
                                 << check.first_colliding.position.y << ", "
                                 << check.first_colliding.position.z << ")";
}

TEST(MotionPlanner, GroundPathGoesThroughAGapClearOfTheTrueObstacles) {
  BoxWorld world = ground_world();
  const PlannerConfig c = ground_config();
  auto planner = MotionPlanner::create(c);
  ASSERT_TRUE(planner.has_value()) << planner.error();
  planner->update_map(world.write(), kStampNs);

  const PlanResult r = planner->plan(request(pose(1, 3), pose(9, 3, 0, 0.5)));
  ASSERT_EQ(r.status, PlanStatus::kOk) << r.message;
  ASSERT_GE(r.path.size(), 3u);  // not straight through the wall
  EXPECT_FALSE(r.stats.direct);
  EXPECT_DOUBLE_EQ(r.path.front().position.x, 1);
  EXPECT_DOUBLE_EQ(r.path.back().position.x, 9);
  EXPECT_DOUBLE_EQ(r.path.back().yaw_rad, 0.5);
  const double y = crossing_y(r.path);
  EXPECT_TRUE(y < 1.5 || y > 4.5) << "crosses x = 5 at y = " << y;
  expect_collision_free(world.truth(), c, r);
  // shortcut: not much longer than around the wall's end (>= 8.4 m), and no longer than
  // the roadmap's path
  EXPECT_LE(r.stats.length_m, r.stats.raw_length_m + 1e-9);
  EXPECT_GT(r.stats.roadmap_vertices, 2u);
}

TEST(MotionPlanner, StraightPathWhenNothingIsInTheWay) {
  BoxWorld world = ground_world();
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanResult r = planner->plan(request(pose(1, 3), pose(3, 5)));
  ASSERT_EQ(r.status, PlanStatus::kOk) << r.message;
  EXPECT_TRUE(r.stats.direct);
  EXPECT_EQ(r.path.size(), 2u);
}

TEST(MotionPlanner, ReusedRoadmapAvoidsAWallAddedInALaterSnapshot) {
  BoxWorld world = ground_world();
  const PlannerConfig c = ground_config();
  auto planner = MotionPlanner::create(c);
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanRequest q = request(pose(1, 3), pose(9, 3));
  const PlanResult first = planner->plan(q);
  ASSERT_EQ(first.status, PlanStatus::kOk) << first.message;
  const double y1 = crossing_y(first.path);
  ASSERT_TRUE(y1 < 1.5 || y1 > 4.5);

  // close the gap the first path took
  const bool took_low = y1 < 1.5;
  world.add_box(V3(4.8, took_low ? 0 : 4.5, 0), V3(5.2, took_low ? 1.5 : 6, 1.2));
  const MapUpdateStats u = planner->update_map(world.write(), kStampNs);
  EXPECT_FALSE(u.rebuilt);
  EXPECT_GT(u.changed_blocks, 0u);
  EXPECT_LT(u.changed_blocks, 20u);  // only the blocks around the new box
  EXPECT_GT(u.forgotten_vertices + u.forgotten_edges, 0u);

  const PlanResult second = planner->plan(q);
  ASSERT_EQ(second.status, PlanStatus::kOk) << second.message;
  EXPECT_FALSE(second.stats.roadmap_cleared);
  const double y2 = crossing_y(second.path);
  EXPECT_TRUE(took_low ? y2 > 4.5 : y2 < 1.5) << "first y " << y1 << ", second y " << y2;
  expect_collision_free(world.truth(), c, second);
}

TEST(MotionPlanner, ReusedRoadmapAnswersLaterQueries) {
  BoxWorld world = ground_world();
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanResult a = planner->plan(request(pose(1, 3), pose(9, 3)));
  ASSERT_EQ(a.status, PlanStatus::kOk);
  const size_t vertices = planner->roadmap_vertices();
  const PlanResult b = planner->plan(request(pose(9, 2.5), pose(1, 3.5, 0, 3.0)));
  ASSERT_EQ(b.status, PlanStatus::kOk) << b.message;
  EXPECT_GE(planner->roadmap_vertices(), vertices);  // kept, not rebuilt
  expect_collision_free(world.truth(), ground_config(), b);
}

TEST(MotionPlanner, MultirotorFliesOverABlockClearOfTheTrueObstacles) {
  // 20 × 12 × 8 m at 0.2 m; a block 5 m tall across the whole width at x in [8, 12]
  BoxWorld world(0.2, Eigen::AlignedBox3d(V3(0, 0, -0.4), V3(20, 12, 8)));
  world.add_box(V3(-1, -1, -0.4), V3(21, 13, 0));
  world.add_box(V3(8, -1, 0), V3(12, 13, 5));
  PlannerConfig c;
  c.robot_kind = RobotKind::kMultirotor;
  c.seed = 1;
  c.collision_check_step_m = 0.1;
  c.multirotor_max_altitude_m = 7.5;
  auto planner = MotionPlanner::create(c);
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanResult r = planner->plan(request(pose(2, 6, 2), pose(18, 6, 2, 1.0)));
  ASSERT_EQ(r.status, PlanStatus::kOk) << r.message;
  double top = 0;
  for (const msg::Waypoint& w : r.path) {
    top = std::max(top, w.position.z);
    EXPECT_LE(w.position.z, 7.5 + 1e-9);
    EXPECT_GE(w.position.z, 1.0 - 1e-9);
  }
  EXPECT_GT(top, 5 + 1.0);  // over the block, the sphere clear of it
  expect_collision_free(world.truth(), c, r);
}

TEST(MotionPlanner, MultirotorMayFlyIntoUnknownSpaceWhenUnknownIsFree) {
  BoxWorld world(0.2, Eigen::AlignedBox3d(V3(0, 0, -0.4), V3(10, 10, 6)));
  world.add_box(V3(-1, -1, -0.4), V3(11, 11, 0));
  PlannerConfig c;
  c.robot_kind = RobotKind::kMultirotor;
  c.unknown_is_occupied = false;
  auto planner = MotionPlanner::create(c);
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanResult r = planner->plan(request(pose(5, 5, 3), pose(11, 5, 3)));
  EXPECT_EQ(r.status, PlanStatus::kOk) << r.message;
}

TEST(MotionPlanner, APathGoesRoundAParkedTeammate) {
  BoxWorld world(0.2, Eigen::AlignedBox3d(V3(0, 0, -0.4), V3(10, 10, 6)));
  world.add_box(V3(-1, -1, -0.4), V3(11, 11, 0));
  PlannerConfig c;
  c.robot_kind = RobotKind::kMultirotor;
  c.seed = 1;
  c.collision_check_step_m = 0.1;
  auto planner = MotionPlanner::create(c);
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanRequest q = request(pose(2, 5, 3), pose(8, 5, 3));
  ASSERT_TRUE(planner->plan(q).stats.direct);  // the roadmap's first query: nothing cached

  // a lost teammate (radius 0.5 m) halfway: the body (1.1 m with the margin) keeps clear
  const V3 teammate(5, 5, 3);
  planner->set_parked({teammate}, 0.5);
  EXPECT_FALSE(planner->is_free(pose(5, 5, 3)));
  EXPECT_FALSE(planner->is_free(pose(5, 6.5, 3)));
  EXPECT_TRUE(planner->is_free(pose(5, 6.7, 3)));
  const PlanResult r = planner->plan(q);
  ASSERT_EQ(r.status, PlanStatus::kOk) << r.message;
  EXPECT_FALSE(r.stats.direct);
  double nearest = 1e9;
  for (size_t i = 1; i < r.path.size(); ++i) {
    const V3 a(r.path[i - 1].position.x, r.path[i - 1].position.y, r.path[i - 1].position.z);
    const V3 b(r.path[i].position.x, r.path[i].position.y, r.path[i].position.z);
    for (int k = 0; k <= 100; ++k)
      nearest = std::min(nearest, (a + (b - a) * (k / 100.0) - teammate).norm());
  }
  EXPECT_GE(nearest, 1.6 - 0.02);

  // back (or gone): the straight path again
  planner->set_parked({}, 0);
  EXPECT_TRUE(planner->plan(q).stats.direct);
}

TEST(MotionPlanner, StartInsideTheWallIsStartInCollision) {
  BoxWorld world = ground_world();
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanResult r = planner->plan(request(pose(5, 3), pose(9, 3)));
  EXPECT_EQ(r.status, PlanStatus::kStartInCollision);
  EXPECT_TRUE(r.path.empty());
  EXPECT_NE(r.message.find("start"), std::string::npos) << r.message;
}

TEST(MotionPlanner, GoalTooCloseToTheWallIsGoalInCollision) {
  BoxWorld world = ground_world();
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  // the centre is free, the ellipse (0.65 m ahead with the margin) reaches the wall
  const PlanResult r = planner->plan(request(pose(1, 3), pose(4.4, 3)));
  EXPECT_EQ(r.status, PlanStatus::kGoalInCollision) << r.message;
}

TEST(MotionPlanner, GoalInUnknownSpaceIsGoalUnknownWhenUnknownIsOccupied) {
  BoxWorld world = ground_world();
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const PlanResult r = planner->plan(request(pose(1, 3), pose(12, 3)));
  EXPECT_EQ(r.status, PlanStatus::kGoalUnknown) << r.message;
}

TEST(MotionPlanner, EnclosedGoalIsNoPathWithinTheTimeLimit) {
  BoxWorld world = ground_world();
  // a closed pen around (8, 3): walls 0.2 m thick enclosing 2 × 2 m of free floor
  world.add_box(V3(6.8, 1.8, 0), V3(9.2, 2.0, 1.2));
  world.add_box(V3(6.8, 4.0, 0), V3(9.2, 4.2, 1.2));
  world.add_box(V3(6.8, 1.8, 0), V3(7.0, 4.2, 1.2));
  world.add_box(V3(9.0, 1.8, 0), V3(9.2, 4.2, 1.2));
  PlannerConfig c = ground_config();
  c.planner_time_limit_s = 0.3;
  auto planner = MotionPlanner::create(c);
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  ASSERT_TRUE(planner->is_free(pose(8, 3)));
  const PlanResult r = planner->plan(request(pose(1, 3), pose(8, 3)));
  EXPECT_EQ(r.status, PlanStatus::kTimeout) << r.message;
  EXPECT_LT(r.stats.total_ms, 1000 * c.planner_time_limit_s + 700);
  // the planner is still usable: a reachable goal next
  const PlanResult ok = planner->plan(request(pose(1, 3), pose(6, 5.3)));
  EXPECT_EQ(ok.status, PlanStatus::kOk) << ok.message;
}

TEST(MotionPlanner, NonFinitePoseIsBadInput) {
  BoxWorld world = ground_world();
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(planner->plan(request(pose(nan, 3), pose(9, 3))).status, PlanStatus::kBadInput);
  EXPECT_EQ(planner->plan(request(pose(1, 3), pose(9, 3, 0, nan))).status, PlanStatus::kBadInput);
  EXPECT_EQ(
      planner->plan(request(pose(1, 3), pose(9, std::numeric_limits<double>::infinity()))).status,
      PlanStatus::kBadInput);
}

TEST(MotionPlanner, NoMapOrAnOldMapIsMapStale) {
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  EXPECT_EQ(planner->plan(request(pose(1, 3), pose(9, 3))).status, PlanStatus::kMapStale);
  BoxWorld world = ground_world();
  planner->update_map(world.write(), kStampNs);
  PlanRequest q = request(pose(1, 3), pose(3, 3));
  q.pose_stamp_ns = kStampNs + 3'000'000'000;  // 3 s after the map; 2 s allowed
  const PlanResult r = planner->plan(q);
  EXPECT_EQ(r.status, PlanStatus::kMapStale);
  EXPECT_NE(r.message.find("older"), std::string::npos) << r.message;
  q.pose_stamp_ns = kStampNs + 1'000'000'000;
  EXPECT_EQ(planner->plan(q).status, PlanStatus::kOk);
}

TEST(MotionPlanner, AFailingStatusIsReportedOncePerGoal) {
  BoxWorld world = ground_world();
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  planner->update_map(world.write(), kStampNs);
  size_t first_reports = 0;
  for (int i = 0; i < 5; ++i) {
    const PlanResult r = planner->plan(request(pose(1, 3), pose(12, 3)));
    EXPECT_EQ(r.status, PlanStatus::kGoalUnknown);
    first_reports += r.first_report ? 1 : 0;
  }
  EXPECT_EQ(first_reports, 1u);
  // another goal: reported again
  EXPECT_TRUE(planner->plan(request(pose(1, 3), pose(12, 4))).first_report);
}

}  // namespace
}  // namespace scancrew::motion
