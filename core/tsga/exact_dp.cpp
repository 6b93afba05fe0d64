#include "core/tsga/exact_dp.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace scancrew::tsga {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Result<void, std::string> check_size(size_t n) {
  if (n > kMaxExactNodes)
    return make_unexpected("the exact DP handles at most " + std::to_string(kMaxExactNodes) +
                           " nodes; got " + std::to_string(n));
  return {};
}

// The cheapest path from source through every node, plus end_cost(last node). arc is an
// n x n row-major matrix of costs in (-inf, +inf]. Ties and all-infinite choices keep the
// first candidate, so a path is always returned.
std::vector<int> held_karp(const std::vector<double>& arc, size_t n, size_t source,
                           const std::vector<double>& end_cost) {
  std::vector<size_t> others;
  for (size_t v = 0; v < n; ++v)
    if (v != source) others.push_back(v);
  const size_t m = others.size();
  std::vector<int> path{static_cast<int>(source)};
  if (m == 0) return path;
  const size_t full = (size_t{1} << m) - 1;
  std::vector<double> dp((full + 1) * m, kInf);
  std::vector<int16_t> parent((full + 1) * m, -1);
  for (size_t j = 0; j < m; ++j) dp[(size_t{1} << j) * m + j] = arc[source * n + others[j]];
  for (size_t mask = 1; mask <= full; ++mask) {
    for (size_t k = 0; k < m; ++k) {
      const size_t bit = size_t{1} << k;
      if ((mask & bit) == 0 || mask == bit) continue;
      const size_t prev_mask = mask ^ bit;
      double best = kInf;
      int16_t best_j = -1;
      for (size_t j = 0; j < m; ++j) {
        if ((prev_mask & (size_t{1} << j)) == 0) continue;
        const double v = dp[prev_mask * m + j] + arc[others[j] * n + others[k]];
        if (best_j < 0 || v < best) {
          best = v;
          best_j = static_cast<int16_t>(j);
        }
      }
      dp[mask * m + k] = best;
      parent[mask * m + k] = best_j;
    }
  }
  double best = kInf;
  int last = -1;
  for (size_t j = 0; j < m; ++j) {
    const double v = dp[full * m + j] + end_cost[others[j]];
    if (last < 0 || v < best) {
      best = v;
      last = static_cast<int>(j);
    }
  }
  std::vector<int> reversed;
  size_t mask = full;
  while (last >= 0) {
    reversed.push_back(static_cast<int>(others[static_cast<size_t>(last)]));
    const int16_t p = parent[mask * m + static_cast<size_t>(last)];
    mask ^= size_t{1} << static_cast<size_t>(last);
    last = p;
  }
  path.insert(path.end(), reversed.rbegin(), reversed.rend());
  return path;
}

}  // namespace

Result<Tour, std::string> solve_closed_atsp_exact(const CostMatrix& costs) {
  const size_t n = costs.size();
  if (auto ok = check_size(n); !ok) return make_unexpected(ok.error());
  if (std::string problem = check_costs(costs); !problem.empty()) return make_unexpected(problem);
  std::vector<double> arc(n * n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      arc[i * n + j] = costs(i, j);
    }
  }
  if (n == 0) return Tour{};
  std::vector<double> back(n, 0.0);
  for (size_t j = 1; j < n; ++j) back[j] = arc[j * n];
  Tour tour;
  tour.nodes = held_karp(arc, n, 0, back);
  tour.cost = tour_cost(costs, tour.nodes);
  tour.status = std::isfinite(tour.cost) ? SolveStatus::kExact : SolveStatus::kNoFiniteTour;
  return tour;
}

Result<OpenPath, std::string> solve_max_open_path_exact(const CostMatrix& utility, int start) {
  const size_t n = utility.size();
  if (auto ok = check_size(n); !ok) return make_unexpected(ok.error());
  if (n == 0) return OpenPath{};
  if (start < 0 || static_cast<size_t>(start) >= n)
    return make_unexpected("start node " + std::to_string(start) + " is not in [0, " +
                           std::to_string(n) + ")");
  if (std::string problem = check_utilities(utility); !problem.empty())
    return make_unexpected(problem);
  std::vector<double> arc(n * n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      arc[i * n + j] = -utility(i, j);
    }
  }
  OpenPath path;
  path.nodes = held_karp(arc, n, static_cast<size_t>(start), std::vector<double>(n, 0.0));
  path.utility = path_utility(utility, path.nodes);
  path.status = std::isfinite(path.utility) ? SolveStatus::kExact : SolveStatus::kNoFiniteTour;
  return path;
}

}  // namespace scancrew::tsga
