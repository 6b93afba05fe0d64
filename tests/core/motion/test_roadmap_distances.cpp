// MotionPlanner::roadmap_distances (core/motion/motion_planner.hpp), the
// high-level planner's d(τ_kl) over the low-level planner's roadmap, on hand-built maps:
// distances agree with the lengths of plan()'s paths, are never below the straight line,
// go around a wall, are +inf for an enclosed or invalid target, follow a map change, and
// leave the roadmap usable for plan().

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/motion/motion_planner.hpp"
#include "executors/params.hpp"
#include "tests/core/motion/box_world.hpp"

namespace scancrew::motion {
namespace {

using test::BoxWorld;
using V3 = Eigen::Vector3d;

constexpr int64_t kStampNs = 1'000'000'000;
constexpr double kInf = std::numeric_limits<double>::infinity();

msg::Waypoint pose(double x, double y, double z = 0, double yaw = 0) {
  msg::Waypoint w;
  w.position = {x, y, z};
  w.yaw_rad = yaw;
  return w;
}

PlannerConfig ground_config() {
  PlannerConfig c;
  c.robot_kind = RobotKind::kGround;
  c.seed = 1;
  c.collision_check_step_m = 0.05;
  return c;
}

// 10 × 6 m observed at 0.1 m, a floor, and a wall across x = 5 from y = 1.5 to 4.5: two
// 1.5 m gaps, at y < 1.5 and y > 4.5 (beyond the region, y < 0 and y > 6, is unknown).
BoxWorld ground_world() {
  BoxWorld w(0.1, Eigen::AlignedBox3d(V3(0, 0, -0.2), V3(10, 6, 1.2)));
  w.add_box(V3(-1, -1, -0.2), V3(11, 7, 0));  // floor
  w.add_box(V3(4.8, 1.5, 0), V3(5.2, 4.5, 1.2));
  return w;
}

double xy_distance(const msg::Waypoint& a, const msg::Waypoint& b) {
  return std::hypot(a.position.x - b.position.x, a.position.y - b.position.y);
}

double xy_length(const std::vector<msg::Waypoint>& path) {
  double l = 0;
  for (size_t i = 1; i < path.size(); ++i) l += xy_distance(path[i - 1], path[i]);
  return l;
}

MotionPlanner make_planner(const PlannerConfig& c, BoxWorld& world) {
  auto planner = MotionPlanner::create(c);
  EXPECT_TRUE(planner.has_value()) << planner.error();
  planner->update_map(world.write(), kStampNs);
  return std::move(planner).value();
}

TEST(RoadmapDistances, AgreeWithThePlannedPathsAndAreNeverBelowTheStraightLine) {
  BoxWorld world = ground_world();
  const PlannerConfig c = ground_config();
  MotionPlanner planner = make_planner(c, world);
  const msg::Waypoint from = pose(1, 3);
  // behind the wall (three of them), beside it, and in the open
  const std::vector<msg::Waypoint> targets{pose(9, 3),          pose(8, 2.5, 0, 1.0),
                                           pose(9, 4.5, 0, -2), pose(6.5, 0.8),
                                           pose(3, 5),          pose(2, 1.5, 0, 3)};
  const RoadmapDistances d = planner.roadmap_distances(from, targets);
  ASSERT_EQ(d.status, PlanStatus::kOk) << d.message;
  ASSERT_EQ(d.distances_m.size(), targets.size());
  EXPECT_GE(d.roadmap_vertices, static_cast<size_t>(c.roadmap_distance_min_vertices));
  EXPECT_GT(d.collision_checks, 0u);

  for (size_t t = 0; t < targets.size(); ++t) {
    const double straight = xy_distance(from, targets[t]);
    const double dist = d.distances_m[t];
    ASSERT_TRUE(std::isfinite(dist)) << "target " << t;
    EXPECT_GE(dist, straight - 1e-9) << "target " << t;
    const PlanResult p = planner.plan({from, targets[t], kStampNs});
    ASSERT_EQ(p.status, PlanStatus::kOk) << p.message;
    const double planned = xy_length(p.path);
    // plan() takes LazyPRM*'s first roadmap path (A* on the state-space distance, yaw
    // included) and shortcuts it; the distance is the roadmap's shortest in x, y, not
    // shortcut. Both approximate the shortest path: measured within 5 % of each other.
    EXPECT_NEAR(dist, planned, 0.12 * planned + 0.1) << "target " << t;
    if (p.stats.direct) {
      EXPECT_NEAR(dist, straight, 1e-9) << "target " << t;
    }
  }
  // around the wall's end: the body (semi-minor axis 0.35 m with the margin) passes y <= 1.15 or
  // y >= 4.85 at x = 5, so at least 2 · hypot(4, 1.85) from (1, 3) to (9, 3)
  EXPECT_GE(d.distances_m[0], 2 * std::hypot(4.0, 1.85) - 1e-6);
  EXPECT_LE(d.distances_m[0], 11.0);
  EXPECT_NEAR(d.distances_m[4], xy_distance(from, targets[4]), 1e-9);  // in the open
}

TEST(RoadmapDistances, EnclosedOrInvalidTargetsAreInfinite) {
  BoxWorld world = ground_world();
  // a closed pen around (8, 3): walls 0.2 m thick enclosing 2 × 2 m of free floor
  world.add_box(V3(6.8, 1.8, 0), V3(9.2, 2.0, 1.2));
  world.add_box(V3(6.8, 4.0, 0), V3(9.2, 4.2, 1.2));
  world.add_box(V3(6.8, 1.8, 0), V3(7.0, 4.2, 1.2));
  world.add_box(V3(9.0, 1.8, 0), V3(9.2, 4.2, 1.2));
  MotionPlanner planner = make_planner(ground_config(), world);
  ASSERT_TRUE(planner.is_free(pose(8, 3)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<msg::Waypoint> targets{
      pose(8, 3),    // enclosed
      pose(6, 5.3),  // reachable
      pose(12, 3),   // unknown space (unknown_is_occupied)
      pose(4.4, 3),  // the ellipse reaches the wall
      pose(nan, 3),  // not finite
      pose(1, 3, 0, nan),
  };
  const RoadmapDistances d = planner.roadmap_distances(pose(1, 3), targets);
  ASSERT_EQ(d.status, PlanStatus::kOk) << d.message;
  ASSERT_EQ(d.distances_m.size(), targets.size());
  EXPECT_EQ(d.distances_m[0], kInf);
  EXPECT_TRUE(std::isfinite(d.distances_m[1]));
  for (size_t t = 2; t < targets.size(); ++t) EXPECT_EQ(d.distances_m[t], kInf) << "target " << t;
  EXPECT_LT(d.ms, 2000.0);
}

TEST(RoadmapDistances, BadOriginsGiveAStatus) {
  auto planner = MotionPlanner::create(ground_config());
  ASSERT_TRUE(planner.has_value());
  const std::vector<msg::Waypoint> targets{pose(9, 3)};
  EXPECT_EQ(planner->roadmap_distances(pose(1, 3), targets).status, PlanStatus::kMapStale);
  BoxWorld world = ground_world();
  planner->update_map(world.write(), kStampNs);
  const RoadmapDistances in_wall = planner->roadmap_distances(pose(5, 3), targets);
  EXPECT_EQ(in_wall.status, PlanStatus::kStartInCollision);
  EXPECT_TRUE(in_wall.distances_m.empty());
  EXPECT_NE(in_wall.message.find("overlaps"), std::string::npos) << in_wall.message;
  EXPECT_EQ(
      planner->roadmap_distances(pose(std::numeric_limits<double>::infinity(), 3), targets).status,
      PlanStatus::kBadInput);
  // no targets: nothing to measure, not an error
  const RoadmapDistances none = planner->roadmap_distances(pose(1, 3), {});
  EXPECT_EQ(none.status, PlanStatus::kOk);
  EXPECT_TRUE(none.distances_m.empty());
}

TEST(RoadmapDistances, ASparseRoadmapIsGrownFirstUnlessTurnedOff) {
  BoxWorld world = ground_world();
  PlannerConfig c = ground_config();
  c.roadmap_distance_min_vertices = 0;  // never grown: only the straight motions
  MotionPlanner off = make_planner(c, world);
  const std::vector<msg::Waypoint> targets{pose(9, 3), pose(3, 5)};
  const RoadmapDistances bare = off.roadmap_distances(pose(1, 3), targets);
  ASSERT_EQ(bare.status, PlanStatus::kOk);
  EXPECT_EQ(bare.grown_vertices, 0u);
  EXPECT_EQ(bare.distances_m[0], kInf);  // behind the wall, and no roadmap to go around
  EXPECT_NEAR(bare.distances_m[1], xy_distance(pose(1, 3), targets[1]), 1e-9);

  c.roadmap_distance_min_vertices = 300;
  MotionPlanner on = make_planner(c, world);
  const RoadmapDistances grown = on.roadmap_distances(pose(1, 3), targets);
  ASSERT_EQ(grown.status, PlanStatus::kOk);
  EXPECT_GE(grown.grown_vertices, 250u);  // minus the invalid ones deleted by the search
  EXPECT_TRUE(std::isfinite(grown.distances_m[0]));
  // a second query reuses the roadmap: nothing to grow, no edge to check twice
  const RoadmapDistances again = on.roadmap_distances(pose(1, 3), targets);
  EXPECT_LE(again.grown_vertices, grown.removed_vertices);
  EXPECT_DOUBLE_EQ(again.distances_m[0], grown.distances_m[0]);
  EXPECT_LT(again.collision_checks, grown.collision_checks);
}

TEST(RoadmapDistances, FollowAWallAddedInALaterSnapshotAndLeaveTheRoadmapUsable) {
  BoxWorld world = ground_world();
  const PlannerConfig c = ground_config();
  MotionPlanner planner = make_planner(c, world);
  const msg::Waypoint from = pose(1, 3);
  const std::vector<msg::Waypoint> targets{pose(9, 1), pose(9, 5)};
  const RoadmapDistances before = planner.roadmap_distances(from, targets);
  ASSERT_EQ(before.status, PlanStatus::kOk);
  ASSERT_TRUE(std::isfinite(before.distances_m[0]));
  // close the low gap: (9, 1) is now reached through the high one only
  world.add_box(V3(4.8, 0, 0), V3(5.2, 1.5, 1.2));
  planner.update_map(world.write(), kStampNs);
  const RoadmapDistances after = planner.roadmap_distances(from, targets);
  ASSERT_EQ(after.status, PlanStatus::kOk);
  // through the high gap: over y = 4.85 at x = 5, then down to y = 1
  EXPECT_GE(after.distances_m[0], std::hypot(4.0, 1.85) + std::hypot(4.0, 3.85) - 1e-6);
  EXPECT_GT(after.distances_m[0], before.distances_m[0] + 1.0);
  EXPECT_TRUE(std::isfinite(after.distances_m[1]));
  // plan() on the roadmap the distances have pruned
  const PlanResult p = planner.plan({from, targets[0], kStampNs});
  ASSERT_EQ(p.status, PlanStatus::kOk) << p.message;
  const PlanResult q = planner.plan({pose(9, 2.5), pose(1, 3.5, 0, 3.0), kStampNs});
  EXPECT_EQ(q.status, PlanStatus::kOk) << q.message;
}

TEST(RoadmapDistances, MultirotorDistancesGoOverABlock) {
  // 20 × 12 × 8 m at 0.2 m; a block 5 m tall across the whole width at x in [8, 12]
  BoxWorld world(0.2, Eigen::AlignedBox3d(V3(0, 0, -0.4), V3(20, 12, 8)));
  world.add_box(V3(-1, -1, -0.4), V3(21, 13, 0));
  world.add_box(V3(8, -1, 0), V3(12, 13, 5));
  PlannerConfig c;
  c.robot_kind = RobotKind::kMultirotor;
  c.seed = 1;
  c.collision_check_step_m = 0.1;
  c.multirotor_max_altitude_m = 7.5;
  MotionPlanner planner = make_planner(c, world);
  const RoadmapDistances d =
      planner.roadmap_distances(pose(2, 6, 2), {pose(18, 6, 2), pose(5, 6, 3), pose(18, 6, 9)});
  ASSERT_EQ(d.status, PlanStatus::kOk) << d.message;
  // up over z = 6.1 (the sphere clear of the top) and down again
  EXPECT_GE(d.distances_m[0], 2 * std::hypot(6.0, 4.1) + 4 - 1e-6);
  EXPECT_LE(d.distances_m[0], 30.0);
  EXPECT_NEAR(d.distances_m[1], std::hypot(3.0, 1.0), 1e-9);  // x, y, z
  EXPECT_EQ(d.distances_m[2], kInf);                          // above the altitude limit
}

}  // namespace
}  // namespace scancrew::motion
