// The engine's steady state: kicks, local searches and restores allocate nothing once the
// engine is built, and each kick + repair keeps a valid tour.

#include <gtest/gtest.h>

#include <vector>

#include "components/tsga/atsp.hpp"
#include "components/tsga/ils_engine.hpp"
#include "tests/components/tsga/allocation_counter.hpp"
#include "tests/components/tsga/random_instances.hpp"

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

}  // namespace
}  // namespace scancrew::tsga
