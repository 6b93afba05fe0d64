#pragma once

// Random test instances with fixed seeds: uniform integer costs (no structure, the
// heuristic's worst case), and utility matrices of the thesis's form (eq. 2.3) over
// clusters at random positions in a 65 x 42 x 15 m box (the Powerplant's size).

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "core/tsga/atsp.hpp"
#include "core/tsga/utility.hpp"

namespace scancrew::tsga::test {

inline CostMatrix random_costs(size_t n, uint32_t seed, int max_cost = 100) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> cost(1, max_cost);
  CostMatrix m(n, 0.0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      if (i != j) m(i, j) = cost(rng);
  return m;
}

// node 0 is the robot ({q_0}, gain 0); nodes 1..clusters are clusters
inline CostMatrix random_utilities(size_t clusters, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const size_t n = clusters + 1;
  std::vector<double> x(n), y(n), z(n), gains(n, 0.0), intra_m(n, 0.0);
  std::vector<uint64_t> ids(n);
  for (size_t i = 0; i < n; ++i) {
    x[i] = 65.0 * u01(rng);
    y[i] = 42.0 * u01(rng);
    z[i] = 15.0 * u01(rng);
    ids[i] = 100 + i;
    if (i > 0) {
      gains[i] = 0.01 + 0.2 * u01(rng);
      intra_m[i] = 10.0 * u01(rng);
    }
  }
  CostMatrix inter(n, 0.0);
  CostMatrix intra(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) {
      inter(i, j) = std::hypot(x[i] - x[j], y[i] - y[j], z[i] - z[j]);
      intra(i, j) = intra_m[j];
    }
  }
  return utility_matrix(ids, gains, inter, intra, {0.1, 0.1}).value();
}

}  // namespace scancrew::tsga::test
