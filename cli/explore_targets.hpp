#pragma once

// Step 11's targets, each with what one `scancrew bench explore` measured and whether it is
// met (explore.md, "Targets"): every run completes the ISE criterion within its budget,
// reaches 95 % of the reachable surface, has an RMSE within 1.5 voxels of its planning map
// and no contact; the thesis's own scenes beaten (the powerplant trio's and five's times and
// coverage, the parking lot's single robot's time and path, four robots' share of one
// robot's time); on the procedural scenes four robots reach 95 % of the reachable surface in
// at most 35 % of one robot's time (mean over the scenes) and the tail after 90 % takes no
// longer than the way to it; five UAVs run at a real-time factor of at least 1.
//
// Times are the monitor's on sim time with compute charged; coverage is the planning map's
// mesh at its own e_max (the thesis's scoring). A target whose runs are missing says so and
// is not met. Pure: no files, no clock.

#include <string>
#include <vector>

#include "cli/explore_table.hpp"

namespace scancrew::cli {

struct TargetVoxels {
  double ground_m = 0.1;      // the ground profile's tsdf_mapper.voxel_m
  double multirotor_m = 0.3;  // the multirotor profile's
};

struct TargetRow {
  std::string target;    // what is asked
  std::string measured;  // what the runs gave, with the run that decides it
  bool met = false;
};

std::vector<TargetRow> explore_targets(const std::vector<ExploreRun>& runs,
                                       const TargetVoxels& voxels);
// "## Targets", the table (target | measured | met), and its notes.
std::string format_targets_markdown(const std::vector<TargetRow>& rows);

}  // namespace scancrew::cli
