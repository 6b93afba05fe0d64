// The high_level_planner's inter_cluster_distance: roadmap (a wall reorders a tour; the
// straight line until the first map; a mixed team's kinds each get their own roadmap), and
// bad configurations failing with the reason.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>

#include "components/high_level_planner/high_level_planner.hpp"
#include "tests/components/high_level_planner/hlp_harness.hpp"
#include "tests/core/motion/box_world.hpp"

namespace scancrew::high_level_planner::test {
namespace {

// --- inter_cluster_distance: roadmap ---

// One ground robot at (4, 1), left of a wall across x = 5 from y = 0 to 4.5 in a 10 × 6 m
// map (the only way past it: y > 4.5). Cluster 100 at (6, 1), 2 m away behind the wall (by
// the roadmap about 8 m, over the wall's end); cluster 101 at (1, 4), 4.2 m away in the
// open. The straight line visits 100 first, the roadmap 101.
const std::string kWallRobot = R"(
  - {id: 1, namespace: r1, kind: ground, start: [4, 1, 0, 0]})";

std::shared_ptr<const tsdf::MapSnapshot> wall_map() {
  using V3 = Eigen::Vector3d;
  motion::test::BoxWorld w(0.1, Eigen::AlignedBox3d(V3(0, 0, -0.2), V3(10, 6, 1.2)));
  w.add_box(V3(-1, -1, -0.2), V3(11, 7, 0));  // floor
  w.add_box(V3(4.8, -1, 0), V3(5.2, 4.5, 1.2));
  return w.write();
}

msg::ViewpointClusters wall_clusters() {
  msg::ViewpointClusters m;
  m.map_version = 3;
  for (const auto& [id, x, y] : {std::tuple<uint32_t, double, double>{100, 6, 1}, {101, 1, 4}}) {
    msg::ViewpointCluster c;
    c.id = id;
    c.gain = 0.1;
    c.robot_types = 3;
    msg::Viewpoint v;
    v.pose.position = {x, y, 0.35};
    v.robot_types = 3;
    c.viewpoints.push_back(v);
    c.centroid = v.pose.position;
    m.clusters.push_back(c);
  }
  return m;
}

const std::string kRoadmapPlanner =
    "{name: hlp, type: high_level_planner, per_robot: false, params: {inter_cluster_distance: "
    "roadmap, planner_seed: 1, collision_check_step_m: 0.05}}";

TEST(HighLevelPlanner, RoadmapDistancesReorderATourAroundAWall) {
  g_script = {};
  g_script.maps = {{0.1, wall_map()}};
  g_script.clusters = {{0.2, wall_clusters()}};
  PlanRun euclidean =
      run(launch_text(kWallRobot, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(euclidean.plans.size(), 1u);
  EXPECT_EQ(euclidean.plans[0].sequences.at(0).cluster_ids, (std::vector<uint32_t>{100, 101}));

  PlanRun roadmap = run(launch_text(kWallRobot, kRoadmapPlanner));
  ASSERT_EQ(roadmap.plans.size(), 1u);
  const msg::PathSequence& s = roadmap.plans[0].sequences.at(0);
  EXPECT_EQ(s.cluster_ids, (std::vector<uint32_t>{101, 100}));
  ASSERT_EQ(s.cluster_utilities.size(), 2u);
  // f = g exp(-λ_tc d): d to 101 is the straight line (x, y: free), on to 100 around the
  // wall's end: at least hypot(4, 0.85) + hypot(1, 3.85) (the body passes y >= 4.85)
  EXPECT_NEAR(s.cluster_utilities[0], 0.1 * std::exp(-0.5 * std::hypot(3.0, 3.0)), 1e-9);
  EXPECT_LT(s.cluster_utilities[1],
            0.1 * std::exp(-0.5 * (std::hypot(4.0, 0.85) + std::hypot(1.0, 3.85))));
  EXPECT_GT(s.cluster_utilities[1], 0.1 * std::exp(-0.5 * 12.0));
  ASSERT_EQ(roadmap.planners.size(), 1u);
  const HighLevelPlanner::Stats& stats = roadmap.planners[0]->stats();
  EXPECT_GE(stats.roadmap_queries, 3u);  // the robot and both clusters' exits
  EXPECT_LE(stats.roadmap_queries, 3u);  // memoised: one row per starting point
  EXPECT_EQ(stats.straight_fallbacks, 0u);
}

TEST(HighLevelPlanner, RoadmapDistancesAreTheStraightLineUntilTheFirstMap) {
  g_script = {};
  g_script.clusters = {{0.1, wall_clusters()}, {0.5, wall_clusters()}};
  g_script.maps = {{0.3, wall_map()}};
  testing::internal::CaptureStderr();
  PlanRun r = run(launch_text(kWallRobot, kRoadmapPlanner));
  const std::string err = testing::internal::GetCapturedStderr();
  ASSERT_EQ(r.plans.size(), 2u);
  EXPECT_EQ(r.plans[0].sequences.at(0).cluster_ids, (std::vector<uint32_t>{100, 101}));
  EXPECT_EQ(r.plans[1].sequences.at(0).cluster_ids, (std::vector<uint32_t>{101, 100}));
  EXPECT_NE(err.find("no map"), std::string::npos) << err;
}

// The wall of wall_map() in a larger map 5 m tall: a ground robot goes round it, a
// multirotor (a 1 m sphere) flies over it (its top at 1.2 m).
std::shared_ptr<const tsdf::MapSnapshot> tall_wall_map() {
  using V3 = Eigen::Vector3d;
  motion::test::BoxWorld w(0.1, Eigen::AlignedBox3d(V3(-2, -2, -0.2), V3(12, 8, 5)));
  w.add_box(V3(-1, -1, -0.2), V3(11, 7, 0));  // floor
  w.add_box(V3(4.8, -1, 0), V3(5.2, 4.5, 1.2));
  return w.write();
}

// Clusters 100 (behind the wall) and 101 (in the open) for ground robots at z 0.35, 200
// (behind the wall, clear of it by its body) and 201 (in the open) for multirotors at z 3.
msg::ViewpointClusters mixed_wall_clusters() {
  msg::ViewpointClusters m;
  m.map_version = 3;
  for (const auto& [id, x, y, z, types] :
       {std::tuple<uint32_t, double, double, double, uint32_t>{100, 6, 1, 0.35, 1},
        {101, 1, 4, 0.35, 1},
        {200, 6.5, 1, 3, 2},
        {201, 1, 4, 3, 2}}) {
    msg::ViewpointCluster c;
    c.id = id;
    c.gain = 0.1;
    c.robot_types = types;
    msg::Viewpoint v;
    v.pose.position = {x, y, z};
    v.robot_types = types;
    c.viewpoints.push_back(v);
    c.centroid = v.pose.position;
    m.clusters.push_back(c);
  }
  return m;
}

TEST(HighLevelPlanner, AMixedTeamGetsEachKindsRoadmapDistances) {
  g_script = {};
  g_script.maps = {{0.1, tall_wall_map()}};
  g_script.clusters = {{0.2, mixed_wall_clusters()}};
  PlanRun r = run(launch_text(R"(
  - {id: 1, namespace: r1, kind: ground, start: [4, 1, 0, 0]}
  - {id: 2, namespace: u2, kind: multirotor, start: [3.5, 1, 3, 0]})",
                              kRoadmapPlanner));
  ASSERT_EQ(r.plans.size(), 1u);
  const msg::PathSequence& ground = r.plans[0].sequences.at(0);
  const msg::PathSequence& uav = r.plans[0].sequences.at(1);
  ASSERT_EQ(ground.robot_id, 1u);
  ASSERT_EQ(uav.robot_id, 2u);
  // the ground robot's way to 100 goes round the wall: it takes 101 first
  EXPECT_EQ(ground.cluster_ids, (std::vector<uint32_t>{101, 100}));
  ASSERT_EQ(ground.cluster_utilities.size(), 2u);
  EXPECT_LT(ground.cluster_utilities[1],
            0.1 * std::exp(-0.5 * (std::hypot(4.0, 0.85) + std::hypot(1.0, 3.85))));
  // the multirotor's is the straight line over the wall (λ_tc 0.3): 200 first, 3 m away
  EXPECT_EQ(uav.cluster_ids, (std::vector<uint32_t>{200, 201}));
  ASSERT_EQ(uav.cluster_utilities.size(), 2u);
  EXPECT_NEAR(uav.cluster_utilities[0], 0.1 * std::exp(-0.3 * 3.0), 1e-9);
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().straight_fallbacks, 0u);
}

TEST(HighLevelPlanner, BadConfigurationsFailWithTheReason) {
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {inter_cluster_distance: roadmap, "
                                      "roadmap_distance_min_vertices: -3}}"))
                .find("roadmap_distance_min_vertices"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {inter_cluster_distance: shortest}}"))
                .find("inter_cluster_distance"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {algorithm: dist_tsga}}"))
                .find("per_robot: true"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround, "{name: hlp, type: high_level_planner}"))
                .find("centralized"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {algorithm: lkh}}"))
                .find("algorithm"),
            std::string::npos);
  EXPECT_NE(config_errors(launch_text(kThreeGround,
                                      "{name: hlp, type: high_level_planner, per_robot: false, "
                                      "params: {ground_lambda_tc_per_m: -1}}"))
                .find("ground_lambda_tc_per_m"),
            std::string::npos);
}

}  // namespace
}  // namespace scancrew::high_level_planner::test
