#pragma once

// The recorded sequence of `scancrew bench perception`: a ground robot driving a loop
// around the parking lot's pillars, recorded through the team simulator, waypoint_driver
// and recorder components on sim time.

#include <cstdint>
#include <string>

#include "core/result.hpp"

namespace scancrew::bench {

struct SequenceOptions {
  std::string scene_path;
  std::string out_path;  // .mcap
  double distance_m = 62.0;
  uint32_t width = 320, height = 256;
  uint64_t seed = 1;
};

struct SequenceInfo {
  double driven_m = 0;  // the driver's odometer (ground truth)
  double sim_s = 0;
  uint64_t messages = 0;
};

// Runs the simulation until the robot has driven distance_m; progress on stderr.
Result<SequenceInfo, std::string> record_sequence(const SequenceOptions& options);

}  // namespace scancrew::bench
