// The high_level_planner component on sim time with the step executor, fed by a scripted
// test component (hlp_harness.hpp): the centralized TSGA plan matches plan_tsga and carries
// yaws, cluster ids and C_start; dist-TSGA on every robot gives TSGA's partition; replan
// requests; an idle robot gets the clusters nobody holds; NNB; a heterogeneous team; bad
// clusters skipped.

#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <set>

#include "components/high_level_planner/high_level_planner.hpp"
#include "tests/components/high_level_planner/hlp_harness.hpp"

namespace scancrew::high_level_planner::test {
namespace {

TEST(HighLevelPlanner, CentralizedTsgaPublishesTheTsgaPlanWithYawsAndIses) {
  const msg::ViewpointClusters clusters = random_clusters(15, 3);
  g_script = {};
  g_script.ises = {{0.1, ises_for(clusters)}};
  g_script.clusters = {{0.2, clusters}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{algorithm: tsga}}"));
  ASSERT_EQ(r.plans.size(), 1u);
  const msg::TeamPlan& plan = r.plans.front();
  EXPECT_EQ(plan.map_version, 7u);
  ASSERT_EQ(plan.sequences.size(), 3u);

  const std::vector<PlanRobot> robots{{.id = 1, .type_bit = 1, .position = {-10, -10, 0}},
                                      {.id = 2, .type_bit = 1, .position = {10, -10, 0}},
                                      {.id = 3, .type_bit = 1, .position = {0, 12, 0}}};
  auto expected = plan_tsga(robots, plan_clusters(clusters));
  ASSERT_TRUE(expected) << expected.error();
  std::multiset<uint32_t> all;
  for (size_t k = 0; k < 3; ++k) {
    const msg::PathSequence& s = plan.sequences[k];
    EXPECT_EQ(s.robot_id, robots[k].id);
    EXPECT_EQ(s.cluster_ids, expected->robots[k].clusters);
    EXPECT_NEAR(s.utility, expected->robots[k].utility, 1e-12);
    ASSERT_EQ(s.cluster_utilities.size(), s.cluster_ids.size());
    ASSERT_EQ(s.viewpoint_clusters.size(), s.viewpoints.size());
    all.insert(s.cluster_ids.begin(), s.cluster_ids.end());
    // every viewpoint is one of its cluster's, with that viewpoint's yaw; C_start holds the
    // ISEs the viewpoints see
    size_t seen = 0;
    for (size_t i = 0; i < s.viewpoints.size(); ++i) {
      const msg::ViewpointCluster& c = clusters.clusters[s.viewpoint_clusters[i] - 100];
      bool found = false;
      for (const msg::Viewpoint& v : c.viewpoints)
        found = found || (v.pose.position.x == s.viewpoints[i].position.x &&
                          v.pose.position.y == s.viewpoints[i].position.y &&
                          v.pose.yaw_rad == s.viewpoints[i].yaw_rad);
      EXPECT_TRUE(found) << "viewpoint " << i << " of robot " << s.robot_id;
      seen += 2;
    }
    EXPECT_EQ(s.ise_centers_m.size(), seen);
  }
  EXPECT_EQ(all.size(), clusters.clusters.size());
  EXPECT_EQ(std::set<uint32_t>(all.begin(), all.end()).size(), clusters.clusters.size());
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().plans, 1u);
}

TEST(HighLevelPlanner, DistTsgaOnEveryRobotGivesTheCentralizedPartition) {
  const msg::ViewpointClusters clusters = random_clusters(20, 11);
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  PlanRun central =
      run(launch_text(kThreeGround, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(central.plans.size(), 1u);

  // every robot's instance reads its own /<ns>/clusters: all three get the same message
  g_script.clusters_topic = "/shared_clusters";
  PlanRun dist = run(launch_text(kThreeGround,
                                 "{name: hlp, type: high_level_planner, remap: {clusters: "
                                 "/shared_clusters}, params: {algorithm: dist_tsga}}"));
  ASSERT_EQ(dist.planners.size(), 3u);
  ASSERT_EQ(dist.plans.size(), 3u);
  std::map<uint32_t, std::vector<uint32_t>> merged;
  for (const msg::TeamPlan& p : dist.plans) {
    ASSERT_EQ(p.sequences.size(), 1u) << "a dist-TSGA robot publishes its own path only";
    merged[p.sequences[0].robot_id] = p.sequences[0].cluster_ids;
  }
  EXPECT_EQ(merged, partition(central.plans.front()));
}

TEST(HighLevelPlanner, AReplanRequestPlansAgainForTheRobotsThisInstancePlansFor) {
  // clusters at 0.2 s: one plan; a request before them (0.1 s) has nothing to plan from; a
  // request at 0.5 s plans again (the centralized instance plans for everyone; of the
  // dist-TSGA instances only the asking robot's plans)
  const msg::ViewpointClusters clusters = random_clusters(12, 5);
  msg::ReplanRequest utility;
  utility.reason = msg::ReplanRequest::Reason::kUtility;
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  g_script.requests = {{0.1, 0, utility}, {0.5, 1, utility}};
  PlanRun central =
      run(launch_text(kThreeGround, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(central.planners.size(), 1u);
  EXPECT_EQ(central.plans.size(), 2u);
  EXPECT_EQ(central.planners[0]->stats().plans, 2u);
  EXPECT_EQ(central.planners[0]->stats().requests, 1u);

  g_script.clusters_topic = "/shared_clusters";
  PlanRun dist = run(launch_text(kThreeGround,
                                 "{name: hlp, type: high_level_planner, remap: {clusters: "
                                 "/shared_clusters}, params: {algorithm: dist_tsga}}"));
  ASSERT_EQ(dist.planners.size(), 3u);
  EXPECT_EQ(dist.plans.size(), 4u);  // one each on the clusters, robot 2's on its request
  for (const HighLevelPlanner* p : dist.planners) {
    const bool asked = p->robot_id() == 2;
    EXPECT_EQ(p->stats().requests, asked ? 1u : 0u) << p->robot_id();
    EXPECT_EQ(p->stats().plans, asked ? 2u : 1u) << p->robot_id();
  }
}

TEST(HighLevelPlanner, AnIdleRobotGetsTheClustersNobodyHolds) {
  const msg::ViewpointClusters first = random_clusters(12, 5);
  msg::ViewpointClusters second = random_clusters(18, 5);  // the first 12 and 6 new ones
  second.map_version = 8;
  // the first 12 with one viewpoint each now: the other robots' plans index viewpoints
  // these clusters no longer hold (an out-of-range crash when their sequences were
  // published again with the idle robot's)
  for (size_t i = 0; i < 12; ++i) second.clusters[i].viewpoints.resize(1);
  g_script = {};
  g_script.clusters = {{0.1, first}, {0.3, second}};  // the second is throttled
  msg::RobotState moving, idle;
  moving.mode = msg::RobotState::Mode::kMoving;
  moving.T_world_body.position = {10, -10, 0};
  idle.mode = msg::RobotState::Mode::kIdle;
  idle.T_world_body.position = {12, -8, 0};
  g_script.states = {{0.2, 1, moving}, {0.5, 1, idle}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{min_replan_period_s: 100}}"));
  ASSERT_EQ(r.plans.size(), 2u);
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().reallocations, 1u);
  EXPECT_EQ(r.planners[0]->stats().skipped, 1u);  // the throttled update
  auto before = partition(r.plans[0]);
  auto after = partition(r.plans[1]);
  // only the idle robot's sequence is published: the others keep their tours
  EXPECT_EQ(after.count(1), 0u);
  EXPECT_EQ(after.count(3), 0u);
  ASSERT_FALSE(after[2].empty());
  std::set<uint32_t> held(before[1].begin(), before[1].end());
  held.insert(before[3].begin(), before[3].end());
  for (uint32_t c : after[2]) EXPECT_EQ(held.count(c), 0u) << c;
  // it takes every cluster nobody else holds (its old ones and the 6 new ones)
  EXPECT_EQ(after[2].size(), second.clusters.size() - held.size());
  EXPECT_EQ(r.plans[1].map_version, 8u);
}

TEST(HighLevelPlanner, NnbGivesEachRobotOneCluster) {
  const msg::ViewpointClusters clusters = random_clusters(10, 2);
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{algorithm: nnb}}"));
  ASSERT_EQ(r.plans.size(), 1u);
  ASSERT_EQ(r.plans[0].sequences.size(), 3u);
  for (const msg::PathSequence& s : r.plans[0].sequences) EXPECT_EQ(s.cluster_ids.size(), 1u);
}

TEST(HighLevelPlanner, HeterogeneousTeamOnlyGetsReachableClusters) {
  msg::ViewpointClusters clusters = random_clusters(12, 9);
  for (size_t i = 0; i < clusters.clusters.size(); ++i)
    clusters.clusters[i].robot_types = i % 3 == 0 ? msg::kMultirotorBit : 3;
  clusters.clusters[5].robot_types = 0;  // nobody can reach it
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  PlanRun r = run(launch_text(R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: u2, kind: multirotor, start: [10, 10, 3, 0]})",
                              "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(r.plans.size(), 1u);
  EXPECT_EQ(r.plans[0].unassigned, std::vector<uint32_t>{105});
  auto p = partition(r.plans[0]);
  for (uint32_t c : p[1]) EXPECT_NE((c - 100) % 3, 0u) << "a UAV-only cluster went to the UGV";
  EXPECT_EQ(p[1].size() + p[2].size(), clusters.clusters.size() - 1);
}

TEST(HighLevelPlanner, BadClustersAreSkippedAndTheNextGoodOnesPlanned) {
  msg::ViewpointClusters bad = random_clusters(6, 4);
  bad.clusters[2].gain = std::numeric_limits<double>::quiet_NaN();
  msg::ViewpointClusters duplicate = random_clusters(6, 4);
  duplicate.clusters[3].id = duplicate.clusters[1].id;
  const msg::ViewpointClusters good = random_clusters(6, 4);
  g_script = {};
  g_script.clusters = {{0.1, bad}, {0.3, duplicate}, {0.5, good}};
  PlanRun r =
      run(launch_text(kThreeGround, "{name: hlp, type: high_level_planner, per_robot: false}"));
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().skipped, 2u);
  ASSERT_EQ(r.plans.size(), 1u);
  size_t assigned = 0;
  for (const msg::PathSequence& s : r.plans[0].sequences) assigned += s.cluster_ids.size();
  EXPECT_EQ(assigned, 6u);
}

}  // namespace
}  // namespace scancrew::high_level_planner::test
