#pragma once

// The parameters of the low-level planner's decision checks, together, and how the
// low_level component reads them from its launch_cfg YAML mapping (flat keys, listed in
// docs/traffic_policy.md). Thesis defaults per robot kind (tables 2.1, 3.1, 4.1, 5.3).

#include <string>

#include "core/motion/check_types.hpp"
#include "core/motion/goal_check.hpp"
#include "core/motion/obstacle_check.hpp"
#include "core/motion/redundancy_check.hpp"
#include "core/motion/traffic_policy.hpp"
#include "core/motion/utility_check.hpp"

namespace scancrew::motion {

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

}  // namespace scancrew::motion
