#pragma once

// Runs of this executable as child processes (scancrew sweep, scancrew bench explore): a
// process of its own per mission, as a run on its own is. In one process, state of a run
// outlives it: OMPL takes its seed once per process, so every run after the first would
// ignore low_level_planner.planner_seed and depend on the runs before it.
//
// A child ends with its parent (PR_SET_PDEATHSIG: SIGTERM). Not thread safe: one thread
// starts and waits for children.

#include <sys/types.h>

#include <string>
#include <vector>

namespace scancrew::cli {

// Starts `scancrew args[1..]` (this executable; args[0] is its argv[0]) with its standard
// output and error appended to log_path (empty: the parent's). Returns its pid, or -1 (said
// on stderr).
pid_t start_child(const std::vector<std::string>& args, const std::string& log_path = {});

// Waits for that child; returns its exit status, 128 + the signal that ended it, or 127.
int wait_child(pid_t pid);

// Waits for whichever child ends first; returns its pid and exit status (as wait_child).
std::pair<pid_t, int> wait_any_child();

}  // namespace scancrew::cli
