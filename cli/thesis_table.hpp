#pragma once

// The thesis's results on its own scenes, and the table that sets `scancrew bench explore`'s
// runs of those scenes beside them (explore.md, "Next to the thesis").
//
//   powerplant: Tables 3.2 (TSGA) and 4.2 (dist-TSGA), simulated UAVs, noisy depth (SR*),
//     10 trials; coverage of the 0.3 m map's mesh at its own e_max.
//   test arena, parking lot: Table 5.4, real ground robots (VIO poses, M3C2 coverage against
//     a scanned model), 5 trials.
//
// Like for like: the bench's runs use the robot kind's profile (the thesis's Tables 3.1 / 5.3
// parameters, r_v 0.3 m for the multirotors), score each mesh at its map's own e_max
// (r_v·√3/2, the thesis's rule) and charge compute on sim time, as the thesis's nodes ran
// in real time. Ours are simulated: ground-truth poses, the noise model of 2.6.1.

#include <string>
#include <vector>

#include "cli/explore_table.hpp"

namespace scancrew::cli {

struct ThesisResult {
  std::string scene;  // as ExploreRun::scene
  size_t robots = 0;
  Architecture arch = Architecture::kSingle;
  std::string table;  // where it comes from: "3.2", "4.2", "5.4"
  double time_s = 0;  // completion time
  double total_path_m = 0;
  double coverage_pct = 0;
};

// The thesis's rows, in table order.
const std::vector<ThesisResult>& thesis_results();

// The thesis's rows with the bench's run of the same scene, team and architecture beside
// them (Markdown, a heading, the table and its notes); rows whose run is not among `runs`
// say so.
std::string format_thesis_markdown(const std::vector<ExploreRun>& runs);

}  // namespace scancrew::cli
