// The engine's steady state: kicks, local searches and restores allocate nothing once the
// engine is built, and each kick + repair keeps a valid tour.

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/tsga/atsp.hpp"
#include "core/tsga/ils_engine.hpp"
#include "tests/core/tsga/allocation_counter.hpp"
#include "tests/core/tsga/random_instances.hpp"

namespace scancrew::tsga {
namespace {

TEST(IlsEngine, KicksAndLocalSearchesAllocateNothing) {
  const size_t n = 120;
  const auto c = test::random_costs(n, 11, 1000);
  std::vector<double> costs(c.values().begin(), c.values().end());
  detail::IlsEngine engine(costs, static_cast<int>(n), 10);
  detail::SplitMix64 rng(3);
  engine.construct_greedy();
  engine.activate_all();
  engine.local_search();
  std::vector<int> best = engine.tour();
  double best_cost = engine.cost();

  // the counter counts
  test::start_counting_allocations();
  std::vector<int> probe;
  probe.reserve(64);
  ASSERT_GE(test::stop_counting_allocations(), 1u);
  ASSERT_NE(probe.data(), nullptr);

  test::start_counting_allocations();
  for (int i = 0; i < 500; ++i) {
    engine.double_bridge(rng);
    engine.local_search();
    const double cost = engine.cost();
    if (cost <= best_cost) {
      best_cost = cost;
      best = engine.tour();  // same size: no allocation
    } else {
      engine.set_tour(best);
    }
  }
  EXPECT_EQ(test::stop_counting_allocations(), 0u);
  EXPECT_TRUE(is_permutation_of_nodes(engine.tour(), n));
  EXPECT_DOUBLE_EQ(engine.cost(), tour_cost(c, engine.tour()));
}

TEST(IlsEngine, EveryKickAndRepairKeepsAValidTourWithATrueCost) {
  for (size_t n : {4, 5, 7, 16, 60}) {
    const auto c = test::random_costs(n, 20 + static_cast<uint32_t>(n));
    std::vector<double> costs(c.values().begin(), c.values().end());
    detail::IlsEngine engine(costs, static_cast<int>(n), 5);
    detail::SplitMix64 rng(n);
    engine.construct_greedy();
    engine.activate_all();
    engine.local_search();
    for (int i = 0; i < 200; ++i) {
      engine.double_bridge(rng);
      ASSERT_TRUE(is_permutation_of_nodes(engine.tour(), n)) << "n " << n << " kick " << i;
      engine.local_search();
      ASSERT_TRUE(is_permutation_of_nodes(engine.tour(), n)) << "n " << n << " kick " << i;
      ASSERT_DOUBLE_EQ(engine.cost(), tour_cost(c, engine.tour()));
    }
  }
}

// Greedy edge as written: every arc sorted by (cost, index), taken when its tail has no
// successor, its head no predecessor and it closes no subtour; the path closed into a tour
// read from its head. The engine pops its arcs from a heap in the same order.
std::vector<int> greedy_by_full_sort(const CostMatrix& c) {
  const int n = static_cast<int>(c.size());
  std::vector<int> arcs;
  for (int a = 0; a < n * n; ++a)
    if (a / n != a % n) arcs.push_back(a);
  const auto cost = [&](int a) {
    return c(static_cast<size_t>(a / n), static_cast<size_t>(a % n));
  };
  std::sort(arcs.begin(), arcs.end(),
            [&](int a, int b) { return cost(a) < cost(b) || (cost(a) == cost(b) && a < b); });
  std::vector<int> next(static_cast<size_t>(n), -1), prev(static_cast<size_t>(n), -1);
  const auto head_of = [&](int v) {
    while (prev[static_cast<size_t>(v)] >= 0) v = prev[static_cast<size_t>(v)];
    return v;
  };
  int added = 0;
  for (int a : arcs) {
    const int i = a / n, j = a % n;
    if (added == n - 1) break;
    if (next[static_cast<size_t>(i)] >= 0 || prev[static_cast<size_t>(j)] >= 0) continue;
    if (head_of(i) == j) continue;  // j heads the path that i ends: a subtour
    next[static_cast<size_t>(i)] = j;
    prev[static_cast<size_t>(j)] = i;
    ++added;
  }
  std::vector<int> tour;
  for (int v = head_of(0); v >= 0; v = next[static_cast<size_t>(v)]) tour.push_back(v);
  return tour;
}

TEST(IlsEngine, GreedyConstructionTakesTheArcsInCostThenIndexOrder) {
  // costs 0..3: most arcs tie, so the index order decides
  for (size_t n : {4, 9, 31, 80}) {
    const auto c = test::random_costs(n, 40 + static_cast<uint32_t>(n), 4);
    std::vector<double> costs(c.values().begin(), c.values().end());
    detail::IlsEngine engine(costs, static_cast<int>(n), 5);
    engine.construct_greedy();
    EXPECT_EQ(engine.tour(), greedy_by_full_sort(c)) << n << " nodes";
  }
}

}  // namespace
}  // namespace scancrew::tsga
