#pragma once

// `scancrew bench explore`: the fixed exploration benchmark (docs/results/explore.md). Every
// mission is composed from a scene, a team and an architecture with the robot kind's
// profile and nothing else (cli/mission_compose.hpp), run with compute charged, in child
// processes (--jobs at a time), each into OUT/runs/<scene>_<arch>_r<N>/:
//   scenes: the thesis's test arena and parking lot (ground robots) and powerplant
//           (multirotors), and 8 procedural scenes (scancrew scenegen): 4 indoor, 4 outdoor,
//           the first seeds whose scenes fit the benchmark's size (explore_bench.cpp);
//   teams:  ground robots 1, 2, 4; multirotors 1, 3, 5; one robot runs "single", a team
//           centralized and distributed;
//   budget: per scene (explore_bench.cpp), the same for every team.
// Resumable: a run whose directory holds its metrics.json and exit status is not run again.
// --quick: the smallest indoor and outdoor scenes of seeds 1-20: a ground pair (centralized
// and distributed) on the indoor budget, one multirotor on a short one; it fails (exit 1)
// when a run failed or wrote inconsistent metrics (check_explore_run), or a ground run did
// not complete, stayed under 95 % of the reachable surface or touched something.
// Writes OUT/explore.md (the family table; the full set adds Step 11's targets, met or not,
// cli/explore_targets.hpp, and the thesis's rows, cli/thesis_table.hpp) and OUT/explore.csv
// after every run; --json prints every run and the summary rows. --only: a subset of the runs (an
// A/B on some rows). --report: the tables of the runs already done under --out, starting none
// (a benchmark stopped part way: the rest read "not run").

#include <cstddef>
#include <string>
#include <vector>

namespace scancrew::cli {

struct ExploreOptions {
  bool json = false;
  bool quick = false;
  size_t jobs = 0;      // 0: the cores of this machine
  std::string out_dir;  // "": runs/bench_explore (runs/bench_explore_quick)
  // not empty: only the runs whose name (<scene>_<arch>_r<N>) contains one of these; the
  // tables then hold those runs only
  std::vector<std::string> only;
  bool report = false;  // write the tables of the runs done, start none
};

int run_explore_bench(const ExploreOptions& options);

}  // namespace scancrew::cli
