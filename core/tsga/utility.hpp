#pragma once

// The arc utilities of the cluster graph (thesis 2.5.1, eq. 2.3):
//   f_UV = g(V) exp(-lambda_tc d(tau_k^l) - lambda_ic d(tau_l^m)),
// with d(tau_k^l) the inter-cluster path length from U into V and d(tau_l^m) the length of
// V's intra-cluster path (entered from U). The matrix is what solve_max_open_path takes;
// node 0 is usually {q_0}, the cluster holding only the robot's current configuration.
//
// Input rules: ids must be unique, gains finite and >= 0, lambdas finite and >= 0, lengths
// >= 0; NaN anywhere is an error. An infinite length (an unreachable cluster) makes the arc
// forbidden (utility -infinity), which the solver avoids when it can.

#include <cstdint>
#include <span>
#include <string>

#include "core/result.hpp"
#include "core/tsga/atsp.hpp"

namespace scancrew::tsga {

struct UtilityWeights {
  double lambda_tc_per_m = 0.1;  // inter-cluster (travel) penalty
  double lambda_ic_per_m = 0.1;  // intra-cluster penalty
};

// ids[i], gains[i]: node i's cluster id and g(V). inter_m, intra_m: n x n, read off the
// diagonal only.
Result<CostMatrix, std::string> utility_matrix(std::span<const uint64_t> ids,
                                               std::span<const double> gains,
                                               const CostMatrix& inter_m, const CostMatrix& intra_m,
                                               const UtilityWeights& weights = {});

}  // namespace scancrew::tsga
