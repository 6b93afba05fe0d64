#pragma once

// Exact (max)ATSP by dynamic programming over subsets (Bellman 1962; Held & Karp 1962;
// thesis appendix B.2.2): O(n^2 2^n) time, O(n 2^n) memory, for n <= kMaxExactNodes. The
// reference the heuristic engine is checked against in the tests.
//
// Same input rules as atsp.hpp: the diagonal is not read, +infinity costs (-infinity
// utilities) are forbidden arcs, NaN is an error. When no tour (path) avoids every
// forbidden arc, the result is one that uses some, with status kNoFiniteTour and an
// infinite value; otherwise the status is kExact.

#include <string>

#include "core/result.hpp"
#include "core/tsga/atsp.hpp"

namespace scancrew::tsga {

inline constexpr size_t kMaxExactNodes = 16;

// The minimum-cost closed tour, starting at node 0.
Result<Tour, std::string> solve_closed_atsp_exact(const CostMatrix& costs);

// The maximum-utility open path from start over all nodes.
Result<OpenPath, std::string> solve_max_open_path_exact(const CostMatrix& utility, int start);

}  // namespace scancrew::tsga
