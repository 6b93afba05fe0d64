#pragma once

// The parameters of the low-level planner's decision checks, together, and how the
// low_level component reads them from its launch_cfg YAML mapping (flat keys, listed in
// docs/traffic_policy.md). Thesis defaults per robot kind (tables 2.1, 3.1, 4.1, 5.3).

#include <string>

#include "components/low_level/check_types.hpp"
#include "components/low_level/goal_check.hpp"
#include "components/low_level/obstacle_check.hpp"
#include "components/low_level/redundancy_check.hpp"
#include "components/low_level/traffic_policy.hpp"
#include "components/low_level/utility_check.hpp"

namespace scancrew {
class ParamReader;
}

namespace scancrew::low_level {

struct ChecksConfig {
  GoalCheckConfig goal;
  UtilityCheckConfig utility;
  ObstacleCheckConfig obstacle;
  TrafficConfig traffic;
  RedundancyConfig redundancy;

  // Thesis defaults for the kind: the safety volume and d0 follow it.
  static ChecksConfig for_kind(RobotKind kind);
  // Empty when valid, else every problem, "; "-separated.
  std::string validate() const;
};

// Reads every check's keys over the defaults for `kind` (the component reads the robot
// kind itself). Range errors and cross-key problems go to the reader's error list, which
// names the file, the line and the key.
ChecksConfig read_checks_config(ParamReader& p, RobotKind kind);

}  // namespace scancrew::low_level
