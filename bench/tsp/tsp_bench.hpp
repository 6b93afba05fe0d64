#pragma once

// `scancrew bench tsp`: the (max)ATSP solver of core/tsga (figures: docs/tsp_bench.md).
//
//   1. TSPLIB: every ATSP instance of data/tsplib_atsp/ solved as a closed tour
//      (solve_closed_atsp, one thread, seed 1, kicks_per_node x n kicks, 1 s time limit):
//      gap to the known optimum (data/tsplib_atsp/ATTRIBUTION.md) and time per instance
//   2. maxATSP: solve_max_open_path from the robot's node over 50, 100 and 200 clusters
//      with the utilities of eq. 2.3 (random positions in a 65 x 42 x 15 m box, random
//      gains and intra-cluster lengths, fixed seeds) and the default SolverOptions, which
//      the planners use: mean and worst time, and the utility against a run with 20 times
//      the kicks
//   3. the targets of the issue, met or missed
//
// Prints {"instances":[{"name","n","optimum","found","gap_pct","ms",...}],
// "max_atsp":[...],"targets":[...]} with --json, else a table. --quick: br17, ftv33 and
// ftv38, two maxATSP instances per size, no long runs (a smoke test).

#include <cstdint>
#include <string>

namespace scancrew::bench {

struct TspBenchOptions {
  std::string dir = "data/tsplib_atsp";  // the TSPLIB .atsp files
  bool quick = false;
  bool json = false;
  uint64_t seed = 1;         // the solver's seed (TSPLIB and maxATSP)
  int kicks_per_node = 500;  // TSPLIB budget: max_iterations = kicks_per_node x n
  int repeats = 5;           // maxATSP instances per size (2 with quick)
};

int run_tsp_bench(const TspBenchOptions& options);

}  // namespace scancrew::bench
