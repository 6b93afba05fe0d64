#pragma once

// The low-level planner's parameters read from a component's launch_cfg YAML mapping: the
// core's (motion::PlannerConfig) and the decision checks' (motion::ChecksConfig). The
// high_level_planner reads the same planner keys for inter_cluster_distance: roadmap.

#include "core/motion/checks_config.hpp"
#include "core/motion/planner_config.hpp"
#include "executors/params.hpp"

namespace scancrew::low_level_planner {

using motion::ChecksConfig;
using motion::PlannerConfig;
using motion::RobotKind;

// Reads the keys named above (robot_type, body_margin_m, unknown_is_occupied, max_map_age_s,
// bounds_margin_m, multirotor_min_altitude_m, multirotor_max_altitude_m, planner_time_limit_s,
// collision_check_step_m, path_cost_factor, roadmap_max_vertices, roadmap_distance_min_vertices,
// roadmap_distance_grow_time_s, guide_grid, goal_tolerance_m, planner_seed); problems are collected
// in the reader. The body is the kind's robot::BodyModel: no key sizes it, so the planner, the
// obstacle check, ISE feasibility and the simulator keep one body.
PlannerConfig read_planner_config(ParamReader& p);

// Reads every check's keys over the defaults for `kind` (the component reads the robot
// kind itself; the obstacle check's safety volume is the kind's body). Range errors and
// cross-key problems go to the reader's error list, which names the file, the line and the key.
ChecksConfig read_checks_config(ParamReader& p, RobotKind kind);

}  // namespace scancrew::low_level_planner
