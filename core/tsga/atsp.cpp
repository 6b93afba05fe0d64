#include "core/tsga/atsp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/tsga/ils_engine.hpp"

namespace scancrew::tsga {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string arc_name(size_t from, size_t to) {
  // appended piece by piece: g++ 12 warns (-Wrestrict, falsely) on "(" + std::to_string()
  std::string name = "(";
  name += std::to_string(from);
  name += ", ";
  name += std::to_string(to);
  name += ")";
  return name;
}

Result<void, std::string> check_options(const SolverOptions& o) {
  if (o.max_iterations < 0)
    return make_unexpected("max_iterations is " + std::to_string(o.max_iterations) +
                           "; allowed: >= 0");
  if (!(o.time_limit_ms >= 0.0))  // also refuses NaN
    return make_unexpected("time_limit_ms is " + std::to_string(o.time_limit_ms) +
                           "; allowed: >= 0 (0 = no limit)");
  if (o.neighbours < 1)
    return make_unexpected("neighbours is " + std::to_string(o.neighbours) + "; allowed: >= 1");
  return {};
}

// The engine's matrix: every off-diagonal cost finite, a forbidden (+infinity) arc replaced
// by a penalty P larger than any difference of two tours without forbidden arcs:
// P + (n - 1) lo > n hi for the cheapest (lo) and dearest (hi) allowed arcs, so a tour
// using a forbidden arc is always dearer than any tour that uses none.
Result<std::vector<double>, std::string> engine_costs(const CostMatrix& costs) {
  const size_t n = costs.size();
  if (std::string problem = check_costs(costs); !problem.empty()) return make_unexpected(problem);
  double lo = kInf;
  double hi = -kInf;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      const double v = costs(i, j);
      if (v == kInf) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (lo > hi) lo = hi = 0.0;  // every arc forbidden
  const double n1 = static_cast<double>(n) + 1.0;
  const double penalty = n1 * (hi - lo) + std::abs(hi) + std::abs(lo) + 1.0;
  if (!std::isfinite(penalty))
    return make_unexpected("arc values up to " + std::to_string(std::max(std::abs(lo), hi)) +
                           " are too large to compare tours; scale them down");
  std::vector<double> out(n * n, 0.0);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j)
      if (i != j) out[i * n + j] = costs(i, j) == kInf ? penalty : costs(i, j);
  return out;
}

SolveStatus heuristic_status(double value, bool time_limited) {
  if (!std::isfinite(value)) return SolveStatus::kNoFiniteTour;
  return time_limited ? SolveStatus::kTimeLimit : SolveStatus::kHeuristic;
}

// n <= 3 (at most two tours): every tour through node 0, compared on the engine's
// finite costs
Tour enumerate_tours(const CostMatrix& costs, const std::vector<double>& finite) {
  const size_t n = costs.size();
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  std::vector<int> best = perm;
  double best_cost = kInf;
  do {
    double sum = 0.0;
    for (size_t p = 0; p < n; ++p)
      sum += finite[static_cast<size_t>(perm[p]) * n + static_cast<size_t>(perm[(p + 1) % n])];
    if (sum < best_cost) {
      best_cost = sum;
      best = perm;
    }
  } while (std::next_permutation(perm.begin() + 1, perm.end()));
  Tour tour;
  tour.nodes = std::move(best);
  tour.cost = tour_cost(costs, tour.nodes);
  tour.status = std::isfinite(tour.cost) ? SolveStatus::kExact : SolveStatus::kNoFiniteTour;
  return tour;
}

}  // namespace

Result<CostMatrix, std::string> CostMatrix::from_values(size_t n, std::vector<double> row_major) {
  if (row_major.size() != n * n)
    return make_unexpected("a " + std::to_string(n) + " x " + std::to_string(n) + " matrix needs " +
                           std::to_string(n * n) + " values, got " +
                           std::to_string(row_major.size()));
  CostMatrix m;
  m.n_ = n;
  m.values_ = std::move(row_major);
  return m;
}

std::string_view to_string(SolveStatus status) {
  switch (status) {
    case SolveStatus::kExact:
      return "exact";
    case SolveStatus::kHeuristic:
      return "heuristic";
    case SolveStatus::kTimeLimit:
      return "time_limit";
    case SolveStatus::kNoFiniteTour:
      return "no_finite_tour";
  }
  return "unknown";
}

double tour_cost(const CostMatrix& costs, std::span<const int> nodes) {
  double sum = 0.0;
  if (nodes.size() < 2) return sum;
  for (size_t p = 0; p < nodes.size(); ++p)
    sum += costs(static_cast<size_t>(nodes[p]), static_cast<size_t>(nodes[(p + 1) % nodes.size()]));
  return sum;
}

double path_utility(const CostMatrix& utility, std::span<const int> nodes) {
  double sum = 0.0;
  for (size_t p = 0; p + 1 < nodes.size(); ++p)
    sum += utility(static_cast<size_t>(nodes[p]), static_cast<size_t>(nodes[p + 1]));
  return sum;
}

bool is_permutation_of_nodes(std::span<const int> nodes, size_t n) {
  if (nodes.size() != n) return false;
  std::vector<char> seen(n, 0);
  for (int v : nodes) {
    if (v < 0 || static_cast<size_t>(v) >= n || seen[static_cast<size_t>(v)] != 0) return false;
    seen[static_cast<size_t>(v)] = 1;
  }
  return true;
}

Result<Tour, std::string> solve_closed_atsp(const CostMatrix& costs, const SolverOptions& options) {
  if (auto ok = check_options(options); !ok) return make_unexpected(ok.error());
  const size_t n = costs.size();
  if (n > kMaxSolverNodes)
    return make_unexpected("a matrix of " + std::to_string(n) + " nodes is too large; at most " +
                           std::to_string(kMaxSolverNodes));
  auto finite = engine_costs(costs);
  if (!finite) return make_unexpected(finite.error());
  if (n == 0) return Tour{};
  if (n <= 3) return enumerate_tours(costs, *finite);

  detail::IlsParams params;
  params.max_iterations = options.max_iterations;
  params.time_limit_ms = options.time_limit_ms;
  params.seed = options.seed;
  params.neighbours = options.neighbours;
  auto outcome = detail::iterated_local_search(*finite, static_cast<int>(n), params);
  Tour tour;
  tour.nodes = std::move(outcome.tour);
  tour.cost = tour_cost(costs, tour.nodes);
  tour.status = heuristic_status(tour.cost, outcome.time_limited);
  tour.iterations = outcome.iterations;
  return tour;
}

std::string check_costs(const CostMatrix& costs) {
  const size_t n = costs.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      const double v = costs(i, j);
      if (std::isnan(v)) return "cost " + arc_name(i, j) + " is NaN";
      if (v == -kInf) return "cost " + arc_name(i, j) + " is -infinity";
    }
  return {};
}

std::string check_utilities(const CostMatrix& utility) {
  const size_t n = utility.size();
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      const double u = utility(i, j);
      if (std::isnan(u)) return "utility " + arc_name(i, j) + " is NaN";
      if (u == kInf) return "utility " + arc_name(i, j) + " is +infinity";
    }
  return {};
}

Result<OpenPath, std::string> solve_max_open_path(const CostMatrix& utility, int start,
                                                  const SolverOptions& options) {
  const size_t n = utility.size();
  if (n == 0) {
    if (auto ok = check_options(options); !ok) return make_unexpected(ok.error());
    return OpenPath{};
  }
  if (start < 0 || static_cast<size_t>(start) >= n)
    return make_unexpected("start node " + std::to_string(start) + " is not in [0, " +
                           std::to_string(n) + ")");
  const auto s = static_cast<size_t>(start);
  if (std::string problem = check_utilities(utility); !problem.empty())
    return make_unexpected(problem);
  // cost(U, V) = -utility(U, V); every arc into the start is the free return arc
  CostMatrix costs(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      const double u = utility(i, j);
      costs(i, j) = j == s ? 0.0 : -u;  // -(-infinity): a forbidden arc
    }
  }
  auto tour = solve_closed_atsp(costs, options);
  if (!tour) return make_unexpected(tour.error());
  OpenPath path;
  path.nodes = std::move(tour->nodes);
  std::rotate(path.nodes.begin(), std::find(path.nodes.begin(), path.nodes.end(), start),
              path.nodes.end());
  path.utility = path_utility(utility, path.nodes);
  path.iterations = tour->iterations;
  path.status = tour->status;
  if (!std::isfinite(path.utility)) path.status = SolveStatus::kNoFiniteTour;
  return path;
}

}  // namespace scancrew::tsga
