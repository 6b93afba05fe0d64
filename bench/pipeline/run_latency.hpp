#pragma once

// `scancrew bench pipeline --run DIR`: camera-to-command latency of a mission run, read from
// its metrics.json (written by `scancrew run`): per robot, the age of the pose behind each
// velocity command (path_tracker: publish time minus the pose's capture stamp), for every
// command and for the first command after each new pose (camera to command), as p50 / p99 /
// max in ms of the run's clock; and, on the wall clock, the simulator's timing (late ticks,
// the physics' largest lag behind the wall). Prints a table, or one JSON object with --json.
// A run directory without metrics.json, or whose robots have no command_latency (a run made
// before it was measured), is an error (exit 1).

#include <string>

namespace scancrew::bench {

int print_run_latency(const std::string& run_dir, bool json);

}  // namespace scancrew::bench
