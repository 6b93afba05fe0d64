// The high_level_planner with lost and idle teammates: a lost robot (kLost, as the
// dds_bridge reports a dead process) is left out and its clusters go to the others, until it
// is back; dist-TSGA plans without a teammate idle too long.

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "components/high_level_planner/high_level_planner.hpp"
#include "tests/components/high_level_planner/hlp_harness.hpp"

namespace scancrew::high_level_planner::test {
namespace {

msg::RobotState state_of(msg::RobotState::Mode mode, const msg::Vec3& position = {}) {
  msg::RobotState s;
  s.mode = mode;
  s.T_world_body.position = position;
  return s;
}

TEST(HighLevelPlanner, ALostRobotIsLeftOutAndItsClustersGoToTheOthersUntilItIsBack) {
  const msg::ViewpointClusters clusters = random_clusters(15, 3);
  g_script = {};
  g_script.clusters = {{0.2, clusters}};
  // robot 2 moving, lost at 0.5 s (the bridge's state: no pose), back at 0.8 s where it
  // started
  g_script.states = {{0.1, 1, state_of(msg::RobotState::Mode::kMoving, {10, -10, 0})},
                     {0.5, 1, state_of(msg::RobotState::Mode::kLost)},
                     {0.8, 1, state_of(msg::RobotState::Mode::kMoving, {10, -10, 0})}};
  PlanRun r = run(launch_text(kThreeGround,
                              "{name: hlp, type: high_level_planner, per_robot: false, params: "
                              "{min_replan_period_s: 100}}"));
  ASSERT_EQ(r.plans.size(), 3u);  // the clusters, robot 2 lost, robot 2 back
  ASSERT_EQ(r.planners.size(), 1u);
  EXPECT_EQ(r.planners[0]->stats().lost_replans, 2u);

  const PlanRobot r1{.id = 1, .type_bit = 1, .position = {-10, -10, 0}};
  const PlanRobot r2{.id = 2, .type_bit = 1, .position = {10, -10, 0}};
  const PlanRobot r3{.id = 3, .type_bit = 1, .position = {0, 12, 0}};
  const auto all = plan_tsga({r1, r2, r3}, plan_clusters(clusters));
  const auto without_2 = plan_tsga({r1, r3}, plan_clusters(clusters));
  ASSERT_TRUE(all && without_2);
  ASSERT_FALSE(all->robots[1].clusters.empty());

  // lost: robot 2 has an empty sequence, robots 1 and 3 share every cluster as TSGA does
  // for the two of them
  auto lost = partition(r.plans[1]);
  ASSERT_EQ(r.plans[1].sequences.size(), 3u);
  EXPECT_TRUE(lost[2].empty());
  EXPECT_TRUE(r.plans[1].sequences[1].viewpoints.empty());
  EXPECT_EQ(lost[1], without_2->robots[0].clusters);
  EXPECT_EQ(lost[3], without_2->robots[1].clusters);
  EXPECT_EQ(lost[1].size() + lost[3].size(), clusters.clusters.size());

  // back: the three-robot plan again
  auto back = partition(r.plans[2]);
  EXPECT_EQ(back[1], all->robots[0].clusters);
  EXPECT_EQ(back[2], all->robots[1].clusters);
  EXPECT_EQ(back[3], all->robots[2].clusters);
  EXPECT_EQ(partition(r.plans[0]), back);
}

TEST(HighLevelPlanner, TwoRobotsOneLostTheOtherTakesEveryCluster) {
  const msg::ViewpointClusters clusters = random_clusters(10, 21);
  const std::string two = R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [10, -10, 0, 0]})";
  for (const bool dist : {false, true}) {
    SCOPED_TRACE(dist ? "dist_tsga" : "tsga");
    g_script = {};
    g_script.clusters_topic = "/shared_clusters";
    g_script.clusters = {{0.2, clusters}};
    g_script.states = {{0.5, 1, state_of(msg::RobotState::Mode::kLost)}};
    PlanRun r = run(launch_text(
        two, dist ? "{name: hlp, type: high_level_planner, remap: {clusters: /shared_clusters}, "
                    "params: {algorithm: dist_tsga}}"
                  : "{name: hlp, type: high_level_planner, per_robot: false, remap: {clusters: "
                    "/shared_clusters}}"));
    // robot 1's latest sequence, and before the loss robot 2 had clusters of its own
    std::vector<uint32_t> mine;
    size_t plans_for_1 = 0;
    bool two_had = false;
    for (const msg::TeamPlan& p : r.plans)
      for (const msg::PathSequence& s : p.sequences) {
        if (s.robot_id == 1) {
          mine = s.cluster_ids;
          ++plans_for_1;
        }
        two_had = two_had || (s.robot_id == 2 && !s.cluster_ids.empty());
      }
    EXPECT_TRUE(two_had);
    EXPECT_EQ(plans_for_1, 2u);  // the clusters, then robot 2 lost
    EXPECT_EQ(std::set<uint32_t>(mine.begin(), mine.end()).size(), clusters.clusters.size());
    EXPECT_EQ(mine.size(), clusters.clusters.size());
    if (!dist) {
      ASSERT_EQ(r.plans.size(), 2u);
      EXPECT_TRUE(partition(r.plans[1])[2].empty());
    }
  }
}

// dist_tsga, idle_teammate_s: a teammate idle that long is planned without (its map may
// lack the clusters this robot sees), so robot 1 takes every cluster; without the rule its
// share stays with the idle robot 2.
TEST(HighLevelPlanner, DistTsgaPlansWithoutATeammateIdleTooLong) {
  const msg::ViewpointClusters clusters = random_clusters(10, 21);
  const std::string two = R"(
  - {id: 1, namespace: r1, kind: ground, start: [-10, -10, 0, 0]}
  - {id: 2, namespace: r2, kind: ground, start: [10, -10, 0, 0]})";
  for (const double idle_s : {0.0, 5.0}) {
    SCOPED_TRACE(idle_s);
    g_script = {};
    g_script.clusters_topic = "/shared_clusters";
    g_script.clusters = {{0.2, clusters}, {7.0, clusters}};
    g_script.states = {{0.1, 1, state_of(msg::RobotState::Mode::kIdle, {10, -10, 0})}};
    PlanRun r = run(launch_text(two,
                                "{name: hlp, type: high_level_planner, remap: {clusters: "
                                "/shared_clusters}, params: {algorithm: dist_tsga, "
                                "idle_teammate_s: " +
                                    std::to_string(idle_s) + "}}",
                                7.5));
    std::vector<uint32_t> first, last;
    for (const msg::TeamPlan& p : r.plans)
      for (const msg::PathSequence& seq : p.sequences)
        if (seq.robot_id == 1) {
          if (first.empty()) first = seq.cluster_ids;
          last = seq.cluster_ids;
        }
    ASSERT_FALSE(first.empty());
    EXPECT_LT(first.size(), clusters.clusters.size()) << "robot 2 has a share at first";
    if (idle_s > 0)
      EXPECT_EQ(std::set<uint32_t>(last.begin(), last.end()).size(), clusters.clusters.size());
    else
      EXPECT_EQ(last, first);
  }
}

}  // namespace
}  // namespace scancrew::high_level_planner::test
