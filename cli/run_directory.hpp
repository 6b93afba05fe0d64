#pragma once

// The run directory of a mission (docs/missions.md, "The run directory"): paths.csv,
// coverage.csv, the best mesh and its map (mesh.ply, map.bt), metrics.json, trace.json and
// report.html, with the summary line printed at the end of `scancrew run`.

#include <filesystem>
#include <string>

#include "cli/choices.hpp"
#include "components/mission_monitor/mission_monitor.hpp"
#include "executors/launch.hpp"

namespace scancrew::cli {

// What the run itself knows, beyond the launch and the monitor.
struct RunFacts {
  std::string launch_path, started;
  StopReason stop_reason = StopReason::kTimeBudget;
  std::filesystem::file_time_type started_at;
  double sim_s = 0, wall_s = 0;
};

// Writes the run directory; returns false (after saying why) if a file could not be written.
bool write_run_directory(const Launch& launch, const mission_monitor::MissionMonitor& monitor,
                         const RunFacts& run, const std::filesystem::path& out);

}  // namespace scancrew::cli
