// Clusters of viewpoints (thesis 2.4.3): connected components of the "closer than d_v"
// graph, an isolated viewpoint joining its nearest one within d_v^max, every viewpoint in
// exactly one cluster, only viewpoints feasible for the same robot types together.

#include <gtest/gtest.h>

#include <vector>

#include "core/ise/clusters.hpp"

namespace scancrew::ise {
namespace {

constexpr uint32_t kAir = robot::kind_bit(RobotKind::kMultirotor);
constexpr uint32_t kGround = robot::kind_bit(RobotKind::kGround);

std::vector<Viewpoint> on_x_axis(const std::vector<double>& xs, uint32_t types = kAir) {
  std::vector<Viewpoint> out;
  for (double x : xs) {
    Viewpoint v;
    v.position = {x, 0.5, 1.0};
    v.type = RobotKind::kMultirotor;
    v.types = types;
    out.push_back(v);
  }
  return out;
}

std::vector<std::vector<uint32_t>> members(const std::vector<Cluster>& clusters) {
  std::vector<std::vector<uint32_t>> out;
  for (const Cluster& c : clusters) out.push_back(c.viewpoints);
  return out;
}

// Every viewpoint index in exactly one cluster; ids are the clusters' indices.
void expect_partition(const std::vector<Cluster>& clusters, size_t n) {
  std::vector<int> count(n, 0);
  for (size_t i = 0; i < clusters.size(); ++i) {
    EXPECT_EQ(clusters[i].id, i);
    EXPECT_FALSE(clusters[i].viewpoints.empty());
    for (uint32_t v : clusters[i].viewpoints) {
      ASSERT_LT(v, n);
      ++count[v];
    }
  }
  for (size_t v = 0; v < n; ++v) EXPECT_EQ(count[v], 1) << "viewpoint " << v;
}

using Members = std::vector<std::vector<uint32_t>>;

TEST(Clusters, ViewpointsSpacedBelowDvFormOneCluster) {
  const auto vps = on_x_axis({0, 1, 2, 3});
  const auto clusters = cluster_viewpoints(vps, 1.5, 2.5);
  EXPECT_EQ(members(clusters), (Members{{0, 1, 2, 3}}));
  expect_partition(clusters, vps.size());
  EXPECT_EQ(clusters[0].types, kAir);
  EXPECT_TRUE(clusters[0].centroid.isApprox(Eigen::Vector3d(1.5, 0.5, 1.0)));
}

TEST(Clusters, GapWiderThanDvMaxSplitsTheLine) {
  // 0 1 2 . . 5 6: a 3 m gap; nobody is isolated, and 3 m > d_v^max anyway
  const auto vps = on_x_axis({0, 1, 2, 5, 6});
  const auto clusters = cluster_viewpoints(vps, 1.5, 2.5);
  EXPECT_EQ(members(clusters), (Members{{0, 1, 2}, {3, 4}}));
  expect_partition(clusters, vps.size());
  EXPECT_TRUE(clusters[1].centroid.isApprox(Eigen::Vector3d(5.5, 0.5, 1.0)));
}

TEST(Clusters, IsolatedViewpointWithinDvMaxJoinsItsNearestCluster) {
  // 4.0 is 2 m from 2: no neighbour within d_v = 1.5, but one within d_v^max = 2.5
  auto vps = on_x_axis({0, 1, 2, 4.0});
  auto clusters = cluster_viewpoints(vps, 1.5, 2.5);
  EXPECT_EQ(members(clusters), (Members{{0, 1, 2, 3}}));
  // 2.8 m: beyond d_v^max, it stays alone
  vps = on_x_axis({0, 1, 2, 4.8});
  clusters = cluster_viewpoints(vps, 1.5, 2.5);
  EXPECT_EQ(members(clusters), (Members{{0, 1, 2}, {3}}));
  expect_partition(clusters, vps.size());
  // d_v^max = d_v: no growth
  vps = on_x_axis({0, 1, 2, 4.0});
  EXPECT_EQ(members(cluster_viewpoints(vps, 1.5, 1.5)), (Members{{0, 1, 2}, {3}}));
}

TEST(Clusters, IsolatedViewpointJoinsOnlyTheNearestAndDoesNotBridgeClusters) {
  // 3.2 is 2.2 m from 1 and 2.8 m from 6; both within d_v^max = 3
  const auto vps = on_x_axis({0, 1, 6, 7, 3.2});
  const auto clusters = cluster_viewpoints(vps, 1.5, 3.0);
  EXPECT_EQ(members(clusters), (Members{{0, 1, 4}, {2, 3}}));
  expect_partition(clusters, vps.size());
}

TEST(Clusters, TwoIsolatedViewpointsWithinDvMaxFormAPair) {
  const auto vps = on_x_axis({0, 2, 10});
  const auto clusters = cluster_viewpoints(vps, 1.5, 2.5);
  EXPECT_EQ(members(clusters), (Members{{0, 1}, {2}}));
}

TEST(Clusters, ViewpointsOfDifferentRobotTypesAreNeverClusteredTogether) {
  auto vps = on_x_axis({0, 0.5, 1.0});
  vps[1].types = kGround;
  vps[2].types = kGround | kAir;
  auto clusters = cluster_viewpoints(vps, 1.5, 2.5);
  EXPECT_EQ(members(clusters), (Members{{0}, {1}, {2}}));
  expect_partition(clusters, vps.size());
  EXPECT_EQ(clusters[0].types, kAir);
  EXPECT_EQ(clusters[1].types, kGround);
  EXPECT_EQ(clusters[2].types, kGround | kAir);
  // same types again further on: they join their own kind only (the isolated-growth rule
  // included: 1 and 3 are 1.7 m apart, beyond d_v but within d_v^max)
  vps = on_x_axis({0, 0.2, 0.4, 1.9});
  vps[1].types = kGround;
  vps[3].types = kGround;
  clusters = cluster_viewpoints(vps, 1.5, 2.5);
  EXPECT_EQ(members(clusters), (Members{{0, 2}, {1, 3}}));
}

TEST(Clusters, NoViewpointsGiveNoClusters) {
  EXPECT_TRUE(cluster_viewpoints({}, 1.5, 2.5).empty());
}

}  // namespace
}  // namespace scancrew::ise
