#pragma once

// The results of `scancrew sweep` (cli/sweep_command.hpp): one SweepRun per mission run
// (architecture x robots x seed) read from its metrics.json (docs/missions.md), and the
// tables made of them: sweep.csv (a row per run) and sweep.md (a Markdown table per scene,
// rows architecture x robots, mean ± std over the seeds), in the form of the thesis's
// Table 5.4 (5.5 Results): completion time, time against the single robot's, coverage,
// RMSE, total path length, data exchanged. Pure functions: no files, no clock.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cli/choices.hpp"
#include "core/result.hpp"
#include "report/time_breakdown.hpp"

namespace scancrew::cli {

inline constexpr double kNoValue = NAN;  // a metric metrics.json did not give (null, absent)
inline std::array<double, report::kActivityCount> no_time_share() {
  std::array<double, report::kActivityCount> a;
  a.fill(kNoValue);
  return a;
}

struct SweepRun {
  // what was run
  Architecture arch = Architecture::kSingle;
  size_t robots = 0;  // team size
  int seed = 0;       // 1..N
  std::string run_dir;
  // what metrics.json says; stop_reason kFailed when there is no metrics.json to read
  StopReason stop_reason = StopReason::kFailed;
  std::string error;  // failed: why
  std::string scene;  // the scene file, as the launch file names it
  double completion_time_s = kNoValue;
  double sim_time_s = kNoValue;
  double wall_time_s = kNoValue;
  double coverage = kNoValue;  // in [0, 1]
  double mean_error_m = kNoValue;
  double rmse_m = kNoValue;
  double total_path_length_m = kNoValue;
  double data_exchanged_bytes = kNoValue;
  uint64_t collisions = 0;
  uint64_t replans = 0;
  // Step 10's exploration measures (docs/missions.md, "Where the time goes")
  double coverage_reachable = kNoValue;  // in [0, 1], of the surface the robots can observe
  double idle_share = kNoValue;          // mean over the robots, in [0, 1]
  double time_to_95_reachable_s = kNoValue;
  double tours_per_goal = kNoValue;
  double m_per_goal = kNoValue;
  // metrics.json's time_share: the robots' mean share of the mission per activity
  // (report/time_breakdown.hpp's order), each in [0, 1]
  std::array<double, report::kActivityCount> time_share = no_time_share();
  std::string compute_time;  // charged | free
};

// `run` with the metrics of a metrics.json text filled in (stop_reason, scene, times,
// coverage, errors, path, data, collisions, replans; null or absent keys stay kNoValue).
// An error (naming `label`) if the text is not a JSON object or has no stop_reason, or one
// that kStopReasonNames does not name.
Result<SweepRun, std::string> read_sweep_metrics(std::string_view json_text, SweepRun run,
                                                 const std::string& label);

// What a run counts for in the tables.
enum class RunOutcome {
  kComplete,     // StopReason::kComplete: its time is its completion time
  kIncomplete,   // kTimeBudget, kStalled: its time is its simulated time, a lower bound
  kInterrupted,  // Ctrl-C: left out of the statistics
  kFailed,       // no metrics.json: left out of the statistics
};
RunOutcome outcome_of(const SweepRun& run);

// Mean and sample standard deviation (n - 1; 0 for one value) of the finite values; n = 0
// (mean and std NaN) if there is none.
struct MeanStd {
  double mean = kNoValue;
  double std = kNoValue;
  size_t n = 0;
};
MeanStd mean_std(const std::vector<double>& values);

// One row of a scene's table: the runs of one architecture and team size.
struct SweepRow {
  std::string scene;
  Architecture arch = Architecture::kSingle;
  size_t robots = 0;
  size_t runs = 0, completed = 0, incomplete = 0, interrupted = 0, failed = 0;
  MeanStd time_s;                    // completion time, or simulated time of incomplete runs
  bool time_is_lower_bound = false;  // an incomplete run is in time_s
  MeanStd coverage_pct, rmse_mm, path_m, data_mb;
  MeanStd coverage_reachable_pct, idle_pct;
  MeanStd t95_reachable_s, tours_per_goal, m_per_goal;
  std::array<MeanStd, report::kActivityCount> time_share_pct;
  uint64_t collisions = 0;  // summed over the runs
};

// The rows, in the order their (scene, arch, robots) first appear in `runs`. A failed run
// with no scene takes the scene of another run of its architecture ("" if none has one).
std::vector<SweepRow> aggregate_sweep(const std::vector<SweepRun>& runs);

// A row's mean time against a reference row's, in percent (thesis: "a team of 4 robots
// reduces the reconstruction time by 31.1 %", i.e. 68.9 %).
struct TimeRatio {
  enum class Bound { kExact, kAtMost, kAtLeast, kUnknown };
  double percent = kNoValue;
  Bound bound = Bound::kUnknown;  // kUnknown: a time missing, or both lower bounds
};
TimeRatio time_ratio(const SweepRow& row, const SweepRow& reference);

// "12.3 ± 0.4" (decimals after the point; the mean alone for one value; "—" for none).
std::string format_mean_std(const MeanStd& value, int decimals);

// sweep.csv: a header and one line per run (empty fields for missing values).
std::string format_sweep_csv(const std::vector<SweepRun>& runs);

// sweep.md: "# title", then per scene a table of aggregate_sweep()'s rows and the notes
// that explain it. The reference for "time vs single" is the scene's single-robot row
// (architecture kSingle, 1 robot), else the row's own architecture with 1 robot.
std::string format_sweep_markdown(const std::vector<SweepRun>& runs, const std::string& title);

}  // namespace scancrew::cli
