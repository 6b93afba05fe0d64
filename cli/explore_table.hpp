#pragma once

// The results of `scancrew bench explore` (cli/explore_bench.hpp): one ExploreRun per
// mission, read from its metrics.json, and the tables made of them: explore.csv (a row per
// run) and explore.md (rows family x team size x architecture: how many completed the ISE
// criterion, times to 90 / 95 % of the reachable surface, completion time, coverage of all
// and of the reachable surface, RMSE, total path, contacts, idle share; means over the
// family's scenes). Pure functions: no files, no clock.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cli/choices.hpp"
#include "cli/sweep_table.hpp"
#include "core/result.hpp"
#include "core/robot/robot_kind.hpp"

namespace scancrew::cli {

struct ExploreRun {
  // what was run
  std::string scene;   // its name: arena, parking_lot, powerplant, indoor_3, ...
  std::string family;  // thesis scenes: their own name; procedural: indoor, outdoor
  robot::RobotKind kind = robot::RobotKind::kGround;
  Architecture arch = Architecture::kSingle;
  size_t robots = 0;
  double budget_s = 0;
  std::string run_dir;
  int exit_status = -1;  // of `scancrew run`; -1: not run
  // what metrics.json says (kNoValue when absent); stop_reason kFailed without it
  StopReason stop_reason = StopReason::kFailed;
  std::string error;
  double completion_time_s = kNoValue;
  double sim_time_s = kNoValue;
  double wall_time_s = kNoValue;
  double t90_reachable_s = kNoValue, t95_reachable_s = kNoValue;
  double coverage = kNoValue, coverage_reachable = kNoValue;
  double rmse_m = kNoValue;
  double total_path_m = kNoValue;
  double contacts = kNoValue;
  double idle_share = kNoValue;
  double breakdown_sum_s = kNoValue;  // the robots' time breakdowns, summed over activities,
                                      // mean over robots (= sim_time_s)
  std::string compute_time;
  std::vector<std::string> places;  // the computers compute was charged on (metrics.json)

  bool completed() const { return stop_reason == StopReason::kComplete; }
  bool ran() const { return stop_reason != StopReason::kFailed; }
};

// run with the fields of a metrics.json text filled in; an error naming label if it is not
// a JSON object with a stop_reason kStopReasonNames names.
Result<ExploreRun, std::string> read_explore_metrics(std::string_view json_text, ExploreRun run,
                                                     const std::string& label);

// What is wrong with a run that ran: metrics missing or inconsistent (the breakdown not
// summing to the mission time within 1 %, coverage outside [0, 1], no reachable coverage).
// Empty when nothing is. The --quick check.
std::string check_explore_run(const ExploreRun& run);

std::string format_explore_csv(const std::vector<ExploreRun>& runs);
// "# title", the table, the notes; `machine` and `command` are printed under the title.
std::string format_explore_markdown(const std::vector<ExploreRun>& runs, const std::string& title,
                                    const std::string& command, const std::string& machine);
// Every run and the summary rows, as JSON text.
std::string format_explore_json(const std::vector<ExploreRun>& runs);

}  // namespace scancrew::cli
