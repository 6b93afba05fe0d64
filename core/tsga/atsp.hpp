#pragma once

// The (max)ATSP solver of the TSGA planners (thesis 2.5.2, 3.4; appendix B.2): the
// maximum-utility open Hamiltonian path from the robot's current node over a set of
// clusters (maxATSP, eq. 2.4), and, on the same engine, the minimum-cost closed
// asymmetric tour (ATSP, eq. B.1) so that it can be measured on TSPLIB.
//
// Engine (ils_engine.hpp): greedy-edge construction, then an iterated local search whose
// local search is the orientation-preserving sequential 3-opt move ("or-3opt", segment
// exchange; Or-opt is its special case) over candidate lists with don't-look bits, kicked
// by segment-local double bridges. The thesis used LKH on a Jonker-Volgenant symmetric
// transformation instead; docs/tsga.md says why and how far apart they are.
//
// Determinism: for a fixed matrix, seed and iteration budget the result is the same on
// every run and machine, unless the time limit (a safety net) stops the search first;
// the status then says kTimeLimit.
//
// Arc values: the diagonal is never read. A +infinity cost (a -infinity utility) is a
// forbidden arc: the solvers avoid it when they can, and report kNoFiniteTour with a cost
// of +infinity (a utility of -infinity) when the tour they return uses one. NaN anywhere
// off the diagonal, a -infinity cost or a +infinity utility is an input error.
//
// Thread safety: every function is reentrant; nothing is shared between calls.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"

namespace scancrew::tsga {

// An n x n matrix of arc values, row-major: (from, to) is the arc from -> to.
class CostMatrix {
 public:
  CostMatrix() = default;
  explicit CostMatrix(size_t n, double fill = 0.0) : n_(n), values_(n * n, fill) {}
  // row_major must hold n * n values
  static Result<CostMatrix, std::string> from_values(size_t n, std::vector<double> row_major);

  size_t size() const { return n_; }
  double operator()(size_t from, size_t to) const { return values_[from * n_ + to]; }
  double& operator()(size_t from, size_t to) { return values_[from * n_ + to]; }
  std::span<const double> values() const { return values_; }

 private:
  size_t n_ = 0;
  std::vector<double> values_;
};

// Stop criteria and knobs. The iteration budget is the primary stop: with it, results are
// deterministic given the seed. The time limit only guards against runaway inputs.
struct SolverOptions {
  int max_iterations = 1000;      // ILS kicks after the first local optimum (>= 0)
  double time_limit_ms = 1000.0;  // wall-clock safety net; 0 = none
  uint64_t seed = 1;              // kick positions and lengths
  int neighbours = 10;            // candidate-list length per node (>= 1)
};

enum class SolveStatus {
  kExact,         // proven optimal (n <= 3 by enumeration, or the exact DP)
  kHeuristic,     // best tour of the local search after the whole iteration budget
  kTimeLimit,     // the time limit stopped the search first: the result depends on speed
  kNoFiniteTour,  // the tour returned uses a forbidden arc (exact DP: no finite tour exists)
};
std::string_view to_string(SolveStatus status);

// A closed tour: every node once, starting at node 0; the arc back to nodes[0] is implied.
struct Tour {
  std::vector<int> nodes;
  double cost = 0.0;  // sum of the n arcs; +infinity if a forbidden arc is used
  SolveStatus status = SolveStatus::kExact;
  int iterations = 0;  // ILS kicks performed
};

// An open path: every node once, starting at the start node, ending anywhere.
struct OpenPath {
  std::vector<int> nodes;
  double utility = 0.0;  // sum of the n - 1 arcs; -infinity if a forbidden arc is used
  SolveStatus status = SolveStatus::kExact;
  int iterations = 0;
};

// The largest n solved: the engine keeps an n x n matrix and sorts the n^2 arcs once.
inline constexpr size_t kMaxSolverNodes = 5000;

// Minimum-cost closed tour over all nodes. n = 0 gives an empty tour of cost 0; n = 1 the
// tour {0} of cost 0 (no arc).
Result<Tour, std::string> solve_closed_atsp(const CostMatrix& costs,
                                            const SolverOptions& options = {});

// maxATSP (eq. 2.4): the open Hamiltonian path from `start` maximising the sum of arc
// utilities utility(U, V). Solved as a closed ATSP with cost(U, V) = -utility(U, V) and a
// free return arc cost(U, start) = 0: a tour through start is then an open path from start
// plus a free arc home, and its cost is minus the path's utility. The column of `start`
// is never used (no arc enters the start). n = 0 gives an empty path (start unused).
Result<OpenPath, std::string> solve_max_open_path(const CostMatrix& utility, int start,
                                                  const SolverOptions& options = {});

// The cost of a closed tour (with the closing arc) and the utility of an open path.
double tour_cost(const CostMatrix& costs, std::span<const int> nodes);
double path_utility(const CostMatrix& utility, std::span<const int> nodes);

// The arc-value rules above: empty when every off-diagonal value is allowed, else the
// first offending arc, named. Costs: no NaN, no -infinity. Utilities: no NaN, no +infinity.
std::string check_costs(const CostMatrix& costs);
std::string check_utilities(const CostMatrix& utility);

// Checks that nodes is a permutation of 0..n-1 (what every solver returns).
bool is_permutation_of_nodes(std::span<const int> nodes, size_t n);

}  // namespace scancrew::tsga
