#pragma once

// The end of a benchmark's report, shared by the benches that print a JSON object or a
// table of their results (ise, planner, tsdf).

#include <nlohmann/json_fwd.hpp>

namespace scancrew::bench {

// Closes `out`: appends the machine's load average after the runs to
// out["load_average_1min"], has `add_targets` add its target lines, then prints `out` on
// stdout as one line of JSON (`json`) or with `print_table`. Returns the exit status: 0
// when no case failed, 1 otherwise.
int finish_report(nlohmann::ordered_json& out, bool json, int failures,
                  void (*add_targets)(nlohmann::ordered_json&),
                  void (*print_table)(const nlohmann::ordered_json&));

}  // namespace scancrew::bench
