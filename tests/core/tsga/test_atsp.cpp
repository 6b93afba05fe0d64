// The ILS engine (closed ATSP and maxATSP) against the exact DP on random small instances,
// on TSPLIB's br17, and on bad input: NaN, infinite arcs, tiny sizes, bad options.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/tsga/atsp.hpp"
#include "core/tsga/exact_dp.hpp"
#include "core/tsga/tsplib.hpp"
#include "tests/core/tsga/random_instances.hpp"

namespace scancrew::tsga {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The check: within 1 % of the DP's optimum in at least 95 % of >= 200 random
// instances of 8 to 14 nodes (here 280 per problem kind, fixed seeds, default options).
TEST(Atsp, ClosedTourIsWithinOnePercentOfTheDpInNinetyFivePercentOfRandomInstances) {
  int within = 0;
  int total = 0;
  int optimal = 0;
  for (size_t n = 8; n <= 14; ++n) {
    for (uint32_t seed = 1; seed <= 40; ++seed) {
      const auto c = test::random_costs(n, 1000 * static_cast<uint32_t>(n) + seed);
      auto exact = solve_closed_atsp_exact(c);
      auto heuristic = solve_closed_atsp(c);
      ASSERT_TRUE(exact && heuristic);
      ASSERT_TRUE(is_permutation_of_nodes(heuristic->nodes, n));
      ASSERT_EQ(heuristic->status, SolveStatus::kHeuristic);
      ASSERT_GE(heuristic->cost, exact->cost - 1e-9);
      ++total;
      within += heuristic->cost <= exact->cost * 1.01 ? 1 : 0;
      optimal += heuristic->cost <= exact->cost + 1e-9 ? 1 : 0;
    }
  }
  std::printf("closed ATSP: %d of %d within 1 %% of the DP, %d optimal\n", within, total, optimal);
  EXPECT_GE(total, 200);
  EXPECT_GE(within, (total * 95 + 99) / 100);
}

TEST(Atsp, MaxOpenPathIsWithinOnePercentOfTheDpInNinetyFivePercentOfRandomInstances) {
  int within = 0;
  int total = 0;
  int optimal = 0;
  for (size_t clusters = 7; clusters <= 13; ++clusters) {
    for (uint32_t seed = 1; seed <= 40; ++seed) {
      const auto u =
          test::random_utilities(clusters, 2000 * static_cast<uint32_t>(clusters) + seed);
      const int start = static_cast<int>(seed % (clusters + 1));
      auto exact = solve_max_open_path_exact(u, start);
      auto heuristic = solve_max_open_path(u, start);
      ASSERT_TRUE(exact && heuristic);
      ASSERT_TRUE(is_permutation_of_nodes(heuristic->nodes, clusters + 1));
      ASSERT_EQ(heuristic->nodes.front(), start);
      ASSERT_DOUBLE_EQ(heuristic->utility, path_utility(u, heuristic->nodes));
      ASSERT_LE(heuristic->utility, exact->utility + 1e-12);
      ++total;
      within += heuristic->utility >= exact->utility * 0.99 ? 1 : 0;
      optimal += heuristic->utility >= exact->utility - 1e-12 ? 1 : 0;
    }
  }
  std::printf("maxATSP: %d of %d within 1 %% of the DP, %d optimal\n", within, total, optimal);
  EXPECT_GE(total, 200);
  EXPECT_GE(within, (total * 95 + 99) / 100);
}

TEST(Atsp, ReachesTheOptimumOfBr17) {
  auto instance = load_tsplib(std::string(SCANCREW_SOURCE_DIR) + "/data/tsplib_atsp/br17.atsp");
  ASSERT_TRUE(instance) << instance.error();
  auto tour = solve_closed_atsp(instance->costs);
  ASSERT_TRUE(tour) << tour.error();
  EXPECT_TRUE(is_permutation_of_nodes(tour->nodes, 17));
  EXPECT_EQ(tour->cost, 39.0);
}

TEST(Atsp, SameSeedGivesTheSameTour) {
  const auto c = test::random_costs(60, 5);
  SolverOptions options;
  options.seed = 42;
  options.max_iterations = 300;
  options.time_limit_ms = 0.0;
  auto a = solve_closed_atsp(c, options);
  auto b = solve_closed_atsp(c, options);
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->nodes, b->nodes);
  EXPECT_EQ(a->cost, b->cost);
  EXPECT_EQ(a->iterations, 300);
  const auto u = test::random_utilities(40, 9);
  auto p = solve_max_open_path(u, 0, options);
  auto q = solve_max_open_path(u, 0, options);
  ASSERT_TRUE(p && q);
  EXPECT_EQ(p->nodes, q->nodes);
}

TEST(Atsp, TimeLimitStopsTheSearchAndSaysSo) {
  SolverOptions options;
  options.max_iterations = 1000000000;
  options.time_limit_ms = 1e-6;
  auto tour = solve_closed_atsp(test::random_costs(100, 3), options);
  ASSERT_TRUE(tour);
  EXPECT_EQ(tour->status, SolveStatus::kTimeLimit);
  EXPECT_TRUE(is_permutation_of_nodes(tour->nodes, 100));
  EXPECT_LT(tour->iterations, 1000);
}

TEST(Atsp, RefusesNaNAndNegativeInfinityWithTheArc) {
  auto c = test::random_costs(10, 1);
  c(4, 7) = kNaN;
  auto nan = solve_closed_atsp(c);
  ASSERT_FALSE(nan);
  EXPECT_EQ(nan.error(), "cost (4, 7) is NaN");
  c(4, 7) = -kInf;
  auto minus = solve_closed_atsp(c);
  ASSERT_FALSE(minus);
  EXPECT_EQ(minus.error(), "cost (4, 7) is -infinity");

  auto u = test::random_utilities(9, 1);
  u(3, 0) = kNaN;  // even an arc into the start, which no path uses
  auto unan = solve_max_open_path(u, 0);
  ASSERT_FALSE(unan);
  EXPECT_EQ(unan.error(), "utility (3, 0) is NaN");
  u(3, 0) = kInf;
  EXPECT_FALSE(solve_max_open_path(u, 0));
}

TEST(Atsp, DiagonalIsNeverRead) {
  auto c = test::random_costs(12, 4);
  auto clean = solve_closed_atsp(c);
  for (size_t v = 0; v < 12; ++v) c(v, v) = kNaN;
  auto dirty = solve_closed_atsp(c);
  ASSERT_TRUE(clean && dirty);
  EXPECT_EQ(clean->nodes, dirty->nodes);
}

TEST(Atsp, AvoidsForbiddenArcsWhenAFiniteTourExists) {
  // 40 % of the arcs forbidden, but a random Hamiltonian cycle kept finite
  const size_t n = 40;
  auto c = test::random_costs(n, 8);
  std::mt19937 rng(8);
  std::vector<size_t> cycle(n);
  for (size_t i = 0; i < n; ++i) cycle[i] = i;
  std::shuffle(cycle.begin(), cycle.end(), rng);
  std::bernoulli_distribution forbid(0.4);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      if (i != j && forbid(rng)) c(i, j) = kInf;
  for (size_t p = 0; p < n; ++p) c(cycle[p], cycle[(p + 1) % n]) = 50.0;
  auto tour = solve_closed_atsp(c);
  ASSERT_TRUE(tour);
  EXPECT_TRUE(std::isfinite(tour->cost));
  EXPECT_EQ(tour->status, SolveStatus::kHeuristic);
}

TEST(Atsp, ReportsNoFiniteTourWhenANodeCannotBeEntered) {
  auto c = test::random_costs(20, 2);
  for (size_t v = 0; v < 20; ++v) c(v, 5) = kInf;
  auto tour = solve_closed_atsp(c);
  ASSERT_TRUE(tour);
  EXPECT_TRUE(is_permutation_of_nodes(tour->nodes, 20));
  EXPECT_EQ(tour->status, SolveStatus::kNoFiniteTour);
  EXPECT_EQ(tour->cost, kInf);

  CostMatrix all(6, kInf);
  auto none = solve_closed_atsp(all);
  ASSERT_TRUE(none);
  EXPECT_TRUE(is_permutation_of_nodes(none->nodes, 6));
  EXPECT_EQ(none->status, SolveStatus::kNoFiniteTour);
}

TEST(Atsp, MaxOpenPathAvoidsForbiddenArcsAndReportsWhenItCannot) {
  auto u = test::random_utilities(12, 3);
  // cluster 4 is unreachable from everywhere but cluster 9
  for (size_t v = 0; v < 13; ++v)
    if (v != 9) u(v, 4) = -kInf;
  auto path = solve_max_open_path(u, 0);
  ASSERT_TRUE(path);
  EXPECT_TRUE(std::isfinite(path->utility));
  const auto it = std::find(path->nodes.begin(), path->nodes.end(), 4);
  ASSERT_NE(it, path->nodes.begin());
  EXPECT_EQ(*(it - 1), 9);

  u(9, 4) = -kInf;  // now unreachable
  auto stuck = solve_max_open_path(u, 0);
  ASSERT_TRUE(stuck);
  EXPECT_EQ(stuck->status, SolveStatus::kNoFiniteTour);
  EXPECT_EQ(stuck->utility, -kInf);
}

TEST(Atsp, HandlesZeroOneTwoAndThreeNodes) {
  auto empty = solve_closed_atsp(CostMatrix());
  ASSERT_TRUE(empty);
  EXPECT_TRUE(empty->nodes.empty());
  EXPECT_EQ(empty->cost, 0.0);
  auto empty_path = solve_max_open_path(CostMatrix(), 0);
  ASSERT_TRUE(empty_path);
  EXPECT_TRUE(empty_path->nodes.empty());

  auto one = solve_closed_atsp(CostMatrix(1, 5.0));
  ASSERT_TRUE(one);
  EXPECT_EQ(one->nodes, std::vector<int>{0});
  EXPECT_EQ(one->cost, 0.0);
  auto one_path = solve_max_open_path(CostMatrix(1, 5.0), 0);
  ASSERT_TRUE(one_path);
  EXPECT_EQ(one_path->nodes, std::vector<int>{0});
  EXPECT_EQ(one_path->utility, 0.0);

  CostMatrix two(2, 0.0);
  two(0, 1) = 2.0;
  two(1, 0) = 3.0;
  auto tour = solve_closed_atsp(two);
  ASSERT_TRUE(tour);
  EXPECT_EQ(tour->cost, 5.0);
  EXPECT_EQ(tour->status, SolveStatus::kExact);
  auto path = solve_max_open_path(two, 1);
  ASSERT_TRUE(path);
  EXPECT_EQ(path->nodes, (std::vector<int>{1, 0}));
  EXPECT_EQ(path->utility, 3.0);

  const auto u = test::random_utilities(2, 5);
  auto three = solve_max_open_path(u, 2);
  auto three_exact = solve_max_open_path_exact(u, 2);
  ASSERT_TRUE(three && three_exact);
  EXPECT_EQ(three->nodes, three_exact->nodes);
  EXPECT_EQ(three->status, SolveStatus::kExact);
}

TEST(Atsp, RefusesABadStartBadOptionsAndHugeValues) {
  const auto u = test::random_utilities(5, 1);
  auto start = solve_max_open_path(u, 6);
  ASSERT_FALSE(start);
  EXPECT_EQ(start.error(), "start node 6 is not in [0, 6)");
  EXPECT_FALSE(solve_max_open_path(u, -1));

  SolverOptions options;
  options.max_iterations = -1;
  auto iterations = solve_closed_atsp(test::random_costs(5, 1), options);
  ASSERT_FALSE(iterations);
  EXPECT_EQ(iterations.error(), "max_iterations is -1; allowed: >= 0");
  options = {};
  options.time_limit_ms = kNaN;
  EXPECT_FALSE(solve_closed_atsp(test::random_costs(5, 1), options));
  options = {};
  options.neighbours = 0;
  EXPECT_FALSE(solve_closed_atsp(test::random_costs(5, 1), options));

  auto huge = test::random_costs(5, 1);
  huge(1, 2) = 1e308;
  huge(2, 1) = -1e308;
  auto refused = solve_closed_atsp(huge);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.error().find("too large"), std::string::npos) << refused.error();

  auto size = CostMatrix::from_values(3, std::vector<double>(8, 1.0));
  ASSERT_FALSE(size);
  EXPECT_EQ(size.error(), "a 3 x 3 matrix needs 9 values, got 8");
}

}  // namespace
}  // namespace scancrew::tsga
