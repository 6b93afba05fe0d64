#pragma once

// `scancrew run <launch.yaml> [--out DIR] [--set name.key=value ...]` (and `scancrew sim`,
// `scancrew robot --robot K`, `scancrew station`: one process of a team, docs/processes.md,
// stepping with the others through its dds_bridge's lockstep): composes the launch
// file and runs it. A launch file with a mission_monitor (components/mission) is a mission:
// it stops when the monitor says the mission is complete (or stalled), when run.duration_s
// (the time budget) is spent, or on Ctrl-C, and in every case writes its run directory
// (docs/missions.md): paths, coverage over time, the mesh and map, metrics.json, trace.json,
// pictures and report.html.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "executors/launch.hpp"

namespace scancrew::cli {

struct RunOptions {
  std::string launch_path;
  std::string out_dir;            // "" = runs/<launch stem>
  std::vector<std::string> sets;  // name.key=value
  size_t robot_count = 0;         // N: the first N robots of the file; 0: as it says
  // missions: per-component compute time and trace.json, at most this many callbacks kept
  // (24 bytes each; beyond it only counted); 0: no tracing
  size_t trace_events = 1'000'000;
  // a team split over processes (docs/processes.md): "run" (all in one), "sim", "robot"
  // (robot_id) or "station"
  std::string process = "run";
  uint32_t robot_id = 0;
  std::string rerun_of;  // scancrew rerun: the run directory it repeats (run.json)
  // --live [PORT]: a foxglove_bridge (the live view, docs/visualization.md) appended to the
  // graph, listening on PORT (0: any free port); -1: none
  int live_port = -1;
};

// 0: ran (a mission: its run directory written); 2: the launch file was refused; 1: the
// run directory could not be written.
int run_launch(const RunOptions& options);

// The launch file at `path` composed (a mission file with `robot_count` robots, 0: as it
// says; live_port ≥ 0: with a foxglove_bridge on that port, in options.process); nullptr after
// printing why not.
std::unique_ptr<Launch> compose_or_report(const std::string& path, const LaunchOptions& options,
                                          size_t robot_count = 0, int live_port = -1);

}  // namespace scancrew::cli
