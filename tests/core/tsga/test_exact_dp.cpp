// The exact DP (Held-Karp) against brute force over every permutation on tiny instances,
// closed tours and open paths, with forbidden arcs and its size limit.

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <numeric>
#include <vector>

#include "core/tsga/exact_dp.hpp"
#include "tests/core/tsga/random_instances.hpp"

namespace scancrew::tsga {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double brute_force_tour(const CostMatrix& c) {
  std::vector<int> perm(c.size());
  std::iota(perm.begin(), perm.end(), 0);
  double best = kInf;
  do {
    best = std::min(best, tour_cost(c, perm));
  } while (std::next_permutation(perm.begin() + 1, perm.end()));
  return best;
}

double brute_force_path(const CostMatrix& u, int start) {
  std::vector<int> rest;
  for (int v = 0; v < static_cast<int>(u.size()); ++v)
    if (v != start) rest.push_back(v);
  double best = -kInf;
  do {
    std::vector<int> path{start};
    path.insert(path.end(), rest.begin(), rest.end());
    best = std::max(best, path_utility(u, path));
  } while (std::next_permutation(rest.begin(), rest.end()));
  return best;
}

TEST(ExactDp, ClosedTourMatchesBruteForceOnTinyInstances) {
  for (size_t n = 2; n <= 8; ++n) {
    for (uint32_t seed = 1; seed <= 5; ++seed) {
      const auto c = test::random_costs(n, seed * 100 + static_cast<uint32_t>(n));
      auto tour = solve_closed_atsp_exact(c);
      ASSERT_TRUE(tour) << tour.error();
      EXPECT_TRUE(is_permutation_of_nodes(tour->nodes, n));
      EXPECT_EQ(tour->nodes.front(), 0);
      EXPECT_EQ(tour->status, SolveStatus::kExact);
      EXPECT_DOUBLE_EQ(tour->cost, tour_cost(c, tour->nodes));
      EXPECT_DOUBLE_EQ(tour->cost, brute_force_tour(c)) << "n " << n << " seed " << seed;
    }
  }
}

TEST(ExactDp, OpenPathMatchesBruteForceFromEveryStart) {
  for (size_t clusters = 1; clusters <= 7; ++clusters) {
    const auto u = test::random_utilities(clusters, 7 + static_cast<uint32_t>(clusters));
    for (int start = 0; start <= static_cast<int>(clusters); ++start) {
      auto path = solve_max_open_path_exact(u, start);
      ASSERT_TRUE(path) << path.error();
      EXPECT_TRUE(is_permutation_of_nodes(path->nodes, clusters + 1));
      EXPECT_EQ(path->nodes.front(), start);
      EXPECT_NEAR(path->utility, brute_force_path(u, start), 1e-12);
    }
  }
}

TEST(ExactDp, AvoidsForbiddenArcsWhenATourExists) {
  // the only finite tour is 0 -> 1 -> 2 -> 3 -> 0
  CostMatrix c(4, kInf);
  for (int v = 0; v < 4; ++v) c(static_cast<size_t>(v), static_cast<size_t>((v + 1) % 4)) = 1.0;
  auto tour = solve_closed_atsp_exact(c);
  ASSERT_TRUE(tour);
  EXPECT_EQ(tour->nodes, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_DOUBLE_EQ(tour->cost, 4.0);
  EXPECT_EQ(tour->status, SolveStatus::kExact);
}

TEST(ExactDp, ReportsNoFiniteTourWhenEveryTourUsesAForbiddenArc) {
  CostMatrix c(5, 1.0);
  for (size_t v = 0; v < 5; ++v) c(v, 3) = kInf;  // nothing may enter node 3
  auto tour = solve_closed_atsp_exact(c);
  ASSERT_TRUE(tour);
  EXPECT_TRUE(is_permutation_of_nodes(tour->nodes, 5));
  EXPECT_EQ(tour->status, SolveStatus::kNoFiniteTour);
  EXPECT_EQ(tour->cost, kInf);
}

TEST(ExactDp, RefusesMoreThanSixteenNodesAndNaN) {
  auto big = solve_closed_atsp_exact(CostMatrix(kMaxExactNodes + 1, 1.0));
  ASSERT_FALSE(big);
  EXPECT_NE(big.error().find("at most 16 nodes; got 17"), std::string::npos) << big.error();
  auto path = solve_max_open_path_exact(CostMatrix(17, 1.0), 0);
  EXPECT_FALSE(path);

  CostMatrix c(4, 1.0);
  c(2, 1) = std::numeric_limits<double>::quiet_NaN();
  auto nan = solve_closed_atsp_exact(c);
  ASSERT_FALSE(nan);
  EXPECT_EQ(nan.error(), "cost (2, 1) is NaN");
}

TEST(ExactDp, HandlesZeroOneAndTwoNodes) {
  auto empty = solve_closed_atsp_exact(CostMatrix());
  ASSERT_TRUE(empty);
  EXPECT_TRUE(empty->nodes.empty());
  auto one = solve_max_open_path_exact(CostMatrix(1, 0.0), 0);
  ASSERT_TRUE(one);
  EXPECT_EQ(one->nodes, std::vector<int>{0});
  EXPECT_EQ(one->utility, 0.0);
  CostMatrix two(2, 0.0);
  two(0, 1) = 3.0;
  two(1, 0) = 4.0;
  auto tour = solve_closed_atsp_exact(two);
  ASSERT_TRUE(tour);
  EXPECT_DOUBLE_EQ(tour->cost, 7.0);
  auto path = solve_max_open_path_exact(two, 1);
  ASSERT_TRUE(path);
  EXPECT_EQ(path->nodes, (std::vector<int>{1, 0}));
  EXPECT_DOUBLE_EQ(path->utility, 4.0);
}

}  // namespace
}  // namespace scancrew::tsga
