#pragma once

// `scancrew sweep <file> --robots 1,2,3,4 --arch single,centralized,distributed --seeds 5`:
// runs a mission for every architecture x team size x seed, one after the other, each as
// `scancrew run` in a child process (as a run on its own: no state carried from one run to
// the next) into its own run directory (docs/missions.md), and writes the results
// as the thesis's tables of 5.5 (Table 5.4: statistics over 5 trials per team):
// DIR/sweep.csv (a row per run) and DIR/sweep.md (mean ± std over the seeds per
// architecture and team size, per scene; cli/sweep_table.hpp), printing sweep.md at the end.
//
// <file> is a sweep file (launch_cfg/missions/<scene>.sweep.yaml: `architectures:` naming
// one launch file per architecture, optional `seed_keys:`) or a plain launch file, which is
// then run for the one architecture --arch names. docs/missions.md, "Sweeps".

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace scancrew::cli {

struct SweepOptions {
  std::string path;                    // sweep file or launch file
  std::vector<size_t> robots;          // team sizes; empty: each launch file's whole robots: list
  std::vector<std::string> archs;      // empty: every architecture of the sweep file
  int seeds = 5;                       // seeds 1..seeds (thesis 5.5: 5 trials)
  std::string out_dir;                 // "" = runs/sweep_<file stem>
  std::vector<std::string> sets;       // name.key=value, for every run (after the seed's)
  std::vector<std::string> seed_keys;  // empty: the sweep file's, else kDefaultSeedKeys
};

// What seed k sets in every run when neither the sweep file nor --seed-keys says (the
// simulator's noise and the low-level planner's sampling of the mission launch files).
inline constexpr std::array<const char*, 2> kDefaultSeedKeys = {"team_simulator.seed",
                                                                "low_level_planner.planner_seed"};

// 0: every run gave its metrics; 1: a run failed (recorded as such; the others still ran)
// or the sweep was stopped (Ctrl-C: after the current run; the tables hold what ran);
// 2: the file or the options were refused (nothing was run).
int run_sweep(const SweepOptions& options);

}  // namespace scancrew::cli
