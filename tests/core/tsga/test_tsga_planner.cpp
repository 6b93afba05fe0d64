// TSGA (Algorithm 2), dist-TSGA (Algorithm 5) and NNB (Algorithm 4) on small teams.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "core/tsga/tsga_planner.hpp"

namespace scancrew::tsga {
namespace {

std::vector<PlanCluster> random_clusters(size_t n, uint64_t seed, double side_m = 20) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0, side_m), gain(0.01, 0.2);
  std::uniform_int_distribution<int> count(1, 4);
  std::vector<PlanCluster> out;
  for (size_t i = 0; i < n; ++i) {
    PlanCluster c;
    c.id = static_cast<uint32_t>(100 + i);
    c.gain = gain(rng);
    const Eigen::Vector3d centre(pos(rng), pos(rng), 0.35);
    for (int k = count(rng); k > 0; --k)
      c.viewpoints.push_back(centre + Eigen::Vector3d(pos(rng), pos(rng), 0) * 0.05);
    out.push_back(c);
  }
  return out;
}

std::vector<PlanRobot> team(size_t n) {
  std::vector<PlanRobot> robots;
  for (size_t i = 0; i < n; ++i)
    robots.push_back({.id = static_cast<uint32_t>(i + 1),
                      .position = Eigen::Vector3d(2.0 + 8.0 * static_cast<double>(i), 1, 0.35)});
  return robots;
}

// cluster id -> robot id
std::map<uint32_t, uint32_t> partition(const TeamPlan& plan) {
  std::map<uint32_t, uint32_t> owner;
  for (const RobotPlan& r : plan.robots)
    for (uint32_t c : r.clusters) EXPECT_TRUE(owner.emplace(c, r.robot_id).second) << c;
  return owner;
}

TEST(Tsga, AssignsEveryClusterExactlyOnce) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const auto clusters = random_clusters(30, seed);
    const auto robots = team(3);
    const auto plan = plan_tsga(robots, clusters);
    ASSERT_TRUE(plan) << plan.error();
    EXPECT_TRUE(plan->unassigned.empty());
    const auto owner = partition(*plan);
    EXPECT_EQ(owner.size(), clusters.size());
    for (const PlanCluster& c : clusters) EXPECT_EQ(owner.count(c.id), 1u) << c.id;
    // each robot's utility is the sum of its arcs, and its path holds its clusters' viewpoints
    for (const RobotPlan& r : plan->robots) {
      double sum = 0;
      for (double f : r.utilities) sum += f;
      EXPECT_NEAR(r.utility, sum, 1e-12);
      size_t viewpoints = 0;
      for (uint32_t id : r.clusters) viewpoints += clusters[id - 100].viewpoints.size();
      EXPECT_EQ(r.viewpoints.size(), viewpoints);
    }
  }
}

TEST(Tsga, NearbyClustersGoToTheNearbyRobot) {
  std::vector<PlanRobot> robots = {{.id = 1, .position = {0, 0, 0}},
                                   {.id = 2, .position = {40, 0, 0}}};
  std::vector<PlanCluster> clusters;
  for (uint32_t i = 0; i < 4; ++i) {
    clusters.push_back({.id = i, .gain = 0.1, .viewpoints = {{1.0 + i, 1, 0}}});
    clusters.push_back({.id = 10 + i, .gain = 0.1, .viewpoints = {{39.0 - i, 1, 0}}});
  }
  const auto plan = plan_tsga(robots, clusters);
  ASSERT_TRUE(plan) << plan.error();
  for (const auto& [cluster, robot] : partition(*plan)) EXPECT_EQ(robot, cluster < 10 ? 1u : 2u);
  // and in the order of the line, nearest first
  EXPECT_EQ(plan->robots[0].clusters, (std::vector<uint32_t>{0, 1, 2, 3}));
  EXPECT_EQ(plan->robots[1].clusters, (std::vector<uint32_t>{10, 11, 12, 13}));
}

TEST(Tsga, ArrivalGainsGiveTheFarEndOfAChainToTheRobotThatGetsThereFirst) {
  // ten clusters 2 m apart along x (2 .. 20 m); robot 1 at the chain's start, robot 2 8 m
  // off its middle. Arc gains (the thesis): every hop of robot 1's chain is 2 m, worth more
  // than robot 2's 8 m to its nearest cluster, so robot 1 takes all ten and robot 2 idles.
  // Arrival gains: robot 1 reaches x = 10 after 10 m, robot 2 after 8 m: robot 2 takes the
  // chain from there on
  const std::vector<PlanRobot> robots = {{.id = 1, .position = {0, 0, 0}},
                                         {.id = 2, .position = {10, 8, 0}}};
  std::vector<PlanCluster> clusters;
  for (uint32_t i = 1; i <= 10; ++i)
    clusters.push_back({.id = i, .gain = 0.1, .viewpoints = {{2.0 * i, 0, 0}}});
  PlannerOptions by_arrival;
  by_arrival.gain = PlannerOptions::Gain::kArrival;
  const auto thesis = plan_tsga(robots, clusters);  // the default: arc gains
  const auto arrival = plan_tsga(robots, clusters, by_arrival);
  ASSERT_TRUE(thesis) << thesis.error();
  ASSERT_TRUE(arrival) << arrival.error();
  EXPECT_EQ(thesis->robots[0].clusters.size(), 10u);
  EXPECT_TRUE(thesis->robots[1].clusters.empty());
  for (const auto& [cluster, robot] : partition(*arrival))
    EXPECT_EQ(robot, cluster < 5 ? 1u : 2u) << "cluster at x = " << 2 * cluster;
  EXPECT_EQ(arrival->robots[0].clusters, (std::vector<uint32_t>{1, 2, 3, 4}));
}

TEST(DistTsga, IdenticalInputsGiveTheTsgaPartitionOnEveryRobot) {
  const auto clusters = random_clusters(25, 7);
  const auto robots = team(4);
  const auto central = plan_tsga(robots, clusters);
  ASSERT_TRUE(central) << central.error();
  std::map<uint32_t, uint32_t> from_robots;
  for (const PlanRobot& r : robots) {
    const auto own = plan_dist_tsga(r.id, robots, clusters);
    ASSERT_TRUE(own) << own.error();
    EXPECT_EQ(own->robot_id, r.id);
    for (uint32_t c : own->clusters) EXPECT_TRUE(from_robots.emplace(c, r.id).second) << c;
  }
  EXPECT_EQ(from_robots, partition(*central));
  EXPECT_FALSE(plan_dist_tsga(99, robots, clusters));  // not in the team
}

TEST(Nnb, GivesOneClusterPerRobotTheMostUseful) {
  const auto clusters = random_clusters(12, 3);
  const auto robots = team(3);
  const auto plan = plan_nnb(robots, clusters);
  ASSERT_TRUE(plan) << plan.error();
  ASSERT_EQ(plan->robots.size(), robots.size());
  for (size_t k = 0; k < robots.size(); ++k) {
    ASSERT_EQ(plan->robots[k].clusters.size(), 1u);
    // no other cluster has a higher utility from the robot's position
    const double best = plan->robots[k].utility;
    for (const PlanCluster& c : clusters) {
      const auto single = plan_nnb({robots[k]}, {c});
      ASSERT_TRUE(single);
      EXPECT_LE(single->robots[0].utility, best + 1e-12);
    }
  }
}

TEST(Tsga, ClustersGoOnlyToRobotTypesThatCanReachThem) {
  auto robots = team(2);
  robots[0].type_bit = 1;  // ground
  robots[1].type_bit = 2;  // multirotor
  auto clusters = random_clusters(10, 11);
  for (size_t i = 0; i < clusters.size(); ++i) clusters[i].robot_types = i % 3 == 0 ? 2u : 1u;
  clusters[4].robot_types = 4;  // a type nobody in the team has
  const auto plan = plan_tsga(robots, clusters);
  ASSERT_TRUE(plan) << plan.error();
  EXPECT_EQ(plan->unassigned, (std::vector<uint32_t>{clusters[4].id}));
  for (const auto& [cluster, robot] : partition(*plan)) {
    const uint32_t types = clusters[cluster - 100].robot_types;
    EXPECT_NE(types & robots[robot - 1].type_bit, 0u) << cluster;
  }
  const auto nnb = plan_nnb(robots, clusters);
  ASSERT_TRUE(nnb);
  EXPECT_EQ(nnb->unassigned, (std::vector<uint32_t>{clusters[4].id}));
}

TEST(Tsga, ReallocationFillsAnIdleRobot) {
  const auto robots = team(3);
  const auto first = random_clusters(12, 21);
  const auto plan = plan_tsga(robots, first);
  ASSERT_TRUE(plan) << plan.error();
  // robot 2 has finished its path (idle); new clusters appeared since
  std::vector<uint32_t> held;
  for (const RobotPlan& r : plan->robots)
    if (r.robot_id != 2) held.insert(held.end(), r.clusters.begin(), r.clusters.end());
  auto now = first;
  for (PlanCluster c : random_clusters(5, 22)) {
    c.id += 1000;
    now.push_back(c);
  }
  now.back().robot_types = 2;  // a multirotor cluster: not for this ground robot
  PlanRobot idle = robots[1];
  idle.position = Eigen::Vector3d(10, 10, 0.35);
  const auto refill = plan_for_idle(idle, now, held);
  ASSERT_TRUE(refill) << refill.error();
  EXPECT_EQ(refill->robot_id, 2u);
  // every cluster nobody else holds and the robot can reach, once, and nothing held
  std::vector<uint32_t> expected;
  for (const PlanCluster& c : now)
    if (std::find(held.begin(), held.end(), c.id) == held.end() && (c.robot_types & 1u) != 0)
      expected.push_back(c.id);
  std::vector<uint32_t> got = refill->clusters;
  std::sort(got.begin(), got.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(got, expected);
  EXPECT_GE(got.size(), 4u);  // at least the new ground clusters
  EXPECT_GT(refill->utility, 0);
  // nothing left: an idle robot stays idle
  std::vector<uint32_t> all;
  for (const PlanCluster& c : now) all.push_back(c.id);
  const auto nothing = plan_for_idle(idle, now, all);
  ASSERT_TRUE(nothing);
  EXPECT_TRUE(nothing->clusters.empty());
}

TEST(Tsga, ACallersTravelDistanceReplacesTheStraightLine) {
  // a wall along x = 10: crossing it costs a 30 m detour; unreachable beyond x = 18
  const auto detour = [](uint32_t, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    if (a.x() > 18 || b.x() > 18) return std::numeric_limits<double>::infinity();
    const double straight = (a - b).norm();
    return (a.x() < 10) != (b.x() < 10) ? straight + 30 : straight;
  };
  PlannerOptions options;
  options.travel_distance = detour;
  std::vector<PlanCluster> clusters = random_clusters(12, 21);
  auto plan = plan_tsga(team(1), clusters, options);
  ASSERT_TRUE(plan) << plan.error();
  const RobotPlan& r = plan->robots.front();
  ASSERT_EQ(r.clusters.size(), clusters.size());
  ASSERT_EQ(r.viewpoint_refs.size(), r.viewpoints.size());
  // each arc's f follows eq. 2.3 with the caller's distance (0 where it is infinite)
  Eigen::Vector3d exit = team(1).front().position;
  size_t at = 0;
  for (size_t i = 0; i < r.clusters.size(); ++i) {
    const PlanCluster& c = clusters[r.clusters[i] - 100];
    const Eigen::Vector3d entry = r.viewpoints[at];
    double intra = 0;
    for (size_t j = 1; j < c.viewpoints.size(); ++j)
      intra += (r.viewpoints[at + j] - r.viewpoints[at + j - 1]).norm();
    const double d = detour(1, exit, entry);
    const double f = std::isinf(d) ? 0.0 : c.gain * std::exp(-0.5 * d - 0.01 * intra);
    EXPECT_NEAR(r.utilities[i], f, 1e-12) << "cluster " << c.id;
    for (size_t j = 0; j < c.viewpoints.size(); ++j) {
      EXPECT_EQ(r.viewpoint_refs[at + j].cluster_id, c.id);
      EXPECT_EQ(c.viewpoints[r.viewpoint_refs[at + j].index], r.viewpoints[at + j]);
    }
    at += c.viewpoints.size();
    exit = r.viewpoints[at - 1];
  }
}

TEST(Tsga, TheTravelDistanceIsAskedForTheRobotsType) {
  // robot 1 (type bit 2) reaches nothing by the caller's distance, robot 2 (bit 1) the
  // straight line: every cluster goes to robot 2
  PlannerOptions options;
  std::set<uint32_t> asked;
  options.travel_distance = [&asked](uint32_t type_bit, const Eigen::Vector3d& a,
                                     const Eigen::Vector3d& b) {
    asked.insert(type_bit);
    return type_bit == 2 ? std::numeric_limits<double>::infinity() : (a - b).norm();
  };
  std::vector<PlanRobot> robots = team(2);
  robots[0].type_bit = 2;
  const std::vector<PlanCluster> clusters = random_clusters(8, 5);
  auto plan = plan_tsga(robots, clusters, options);
  ASSERT_TRUE(plan) << plan.error();
  EXPECT_EQ(asked, (std::set<uint32_t>{1, 2}));
  EXPECT_TRUE(plan->robots[0].clusters.empty());
  EXPECT_EQ(plan->robots[1].clusters.size(), clusters.size());
}

TEST(Tsga, EdgeCasesHaveDefinedResults) {
  const auto robots = team(2);
  const auto none = plan_tsga(robots, {});
  ASSERT_TRUE(none);
  ASSERT_EQ(none->robots.size(), 2u);
  EXPECT_TRUE(none->robots[0].clusters.empty());
  const auto clusters = random_clusters(6, 2);
  const auto nobody = plan_tsga({}, clusters);
  ASSERT_TRUE(nobody);
  EXPECT_EQ(nobody->unassigned.size(), clusters.size());
  const auto single = plan_tsga(team(1), clusters);  // a single robot takes everything
  ASSERT_TRUE(single);
  EXPECT_EQ(single->robots[0].clusters.size(), clusters.size());
}

TEST(Tsga, BadInputIsAClearError) {
  const auto robots = team(2);
  auto clusters = random_clusters(4, 5);
  auto expect_error = [&](const std::vector<PlanRobot>& r, const std::vector<PlanCluster>& c,
                          const std::string& words) {
    const auto plan = plan_tsga(r, c);
    ASSERT_FALSE(plan);
    EXPECT_NE(plan.error().find(words), std::string::npos) << plan.error();
    EXPECT_FALSE(plan_nnb(r, c));
  };
  auto nan_gain = clusters;
  nan_gain[1].gain = std::nan("");
  expect_error(robots, nan_gain, "gain");
  auto duplicate = clusters;
  duplicate[2].id = duplicate[0].id;
  expect_error(robots, duplicate, "duplicate cluster");
  auto empty = clusters;
  empty[3].viewpoints.clear();
  expect_error(robots, empty, "no viewpoints");
  auto nan_robot = robots;
  nan_robot[1].position.x() = std::nan("");
  expect_error(nan_robot, clusters, "not finite");
  auto twins = robots;
  twins[1].id = twins[0].id;
  expect_error(twins, clusters, "duplicate robot");
}

}  // namespace
}  // namespace scancrew::tsga
