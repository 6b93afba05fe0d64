// IntraPathCache: intra-cluster paths kept across TSGA calls give the plan found without it.

#include <gtest/gtest.h>

#include <random>

#include "core/tsga/tsga_planner.hpp"

namespace scancrew::tsga {
namespace {

// clusters of 3 to 12 viewpoints (more than the engine's n <= 3 shortcut)
std::vector<PlanCluster> clusters_of(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(0, 30), offset(-2, 2), gain(0.01, 0.2);
  std::uniform_int_distribution<int> count(3, 12);
  std::vector<PlanCluster> out;
  for (size_t i = 0; i < n; ++i) {
    PlanCluster c{.id = static_cast<uint32_t>(i), .gain = gain(rng), .viewpoints = {}};
    const Eigen::Vector3d centre(pos(rng), pos(rng), 2.0);
    for (int k = count(rng); k > 0; --k)
      c.viewpoints.push_back(centre + Eigen::Vector3d(offset(rng), offset(rng), 0));
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<PlanRobot> trio() {
  return {{.id = 1, .position = {0, 0, 2}},
          {.id = 2, .position = {30, 0, 2}},
          {.id = 3, .position = {15, 30, 2}}};
}

void expect_same(const TeamPlan& a, const TeamPlan& b) {
  ASSERT_EQ(a.robots.size(), b.robots.size());
  for (size_t k = 0; k < a.robots.size(); ++k) {
    EXPECT_EQ(a.robots[k].clusters, b.robots[k].clusters) << "robot " << k;
    EXPECT_EQ(a.robots[k].viewpoints, b.robots[k].viewpoints) << "robot " << k;
    EXPECT_DOUBLE_EQ(a.robots[k].utility, b.robots[k].utility) << "robot " << k;
  }
}

TEST(IntraPathCache, KeptPathsGiveThePlanFoundWithoutThem) {
  auto clusters = clusters_of(25, 3);
  IntraPathCache cache;
  PlannerOptions with;
  with.intra_paths = &cache;
  cache.new_generation();
  const auto first = plan_tsga(trio(), clusters, with);
  ASSERT_TRUE(first) << first.error();
  EXPECT_EQ(cache.stats().misses, 25u);
  EXPECT_EQ(cache.stats().hits, 0u);
  // one cluster moves: it alone is solved again
  for (Eigen::Vector3d& v : clusters[7].viewpoints) v.x() += 0.5;
  cache.new_generation();
  const auto second = plan_tsga(trio(), clusters, with);
  ASSERT_TRUE(second) << second.error();
  EXPECT_EQ(cache.stats().misses, 26u);
  EXPECT_EQ(cache.stats().hits, 24u);
  const auto plain = plan_tsga(trio(), clusters);
  ASSERT_TRUE(plain) << plain.error();
  expect_same(*second, *plain);
}

TEST(IntraPathCache, TheBudgetAndTheSeedArePartOfTheKey) {
  const auto clusters = clusters_of(4, 5);
  IntraPathCache cache;
  PlannerOptions o;
  o.intra_paths = &cache;
  ASSERT_TRUE(plan_tsga(trio(), clusters, o));
  o.insertion_iterations = 5;
  ASSERT_TRUE(plan_tsga(trio(), clusters, o));
  o.seed = 9;
  ASSERT_TRUE(plan_tsga(trio(), clusters, o));
  EXPECT_EQ(cache.stats().misses, 12u);
  EXPECT_EQ(cache.stats().hits, 0u);
}

TEST(IntraPathCache, APathNotAskedForInAGenerationIsDroppedAfterTheNext) {
  const auto clusters = clusters_of(6, 7);
  IntraPathCache cache;
  PlannerOptions o;
  o.intra_paths = &cache;
  cache.new_generation();
  ASSERT_TRUE(plan_tsga(trio(), clusters, o));
  EXPECT_EQ(cache.size(), 6u);
  // a generation that asks for the first two only: the rest wait in the previous one
  cache.new_generation();
  const std::vector<PlanCluster> two(clusters.begin(), clusters.begin() + 2);
  ASSERT_TRUE(plan_tsga(trio(), two, o));
  EXPECT_EQ(cache.stats().hits, 2u);
  EXPECT_EQ(cache.size(), 6u);
  cache.new_generation();
  EXPECT_EQ(cache.size(), 2u);
  ASSERT_TRUE(plan_tsga(trio(), clusters, o));
  EXPECT_EQ(cache.stats().hits, 4u);
  EXPECT_EQ(cache.stats().misses, 10u);
}

}  // namespace
}  // namespace scancrew::tsga
