#include "components/low_level_planner/planner_params.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace scancrew::low_level_planner {

using motion::TrafficConfig;

PlannerConfig read_planner_config(ParamReader& p) {
  PlannerConfig c;
  p.choice("robot_type", c.robot_kind, robot::kRobotKindNames);
  p.optional("body_margin_m", c.body_margin_m, {0, 10});
  p.optional("unknown_is_occupied", c.unknown_is_occupied);
  p.optional("max_map_age_s", c.max_map_age_s, {0, 1e6});
  p.optional("bounds_margin_m", c.bounds_margin_m, {0, 1000});
  p.optional("multirotor_min_altitude_m", c.multirotor_min_altitude_m, {-1e4, 1e4});
  p.optional("multirotor_max_altitude_m", c.multirotor_max_altitude_m, {-1e4, 1e4});
  p.optional("planner_time_limit_s", c.planner_time_limit_s, {1e-3, 3600});
  p.optional("collision_check_step_m", c.collision_check_step_m, {1e-3, 10});
  p.optional("path_cost_factor", c.path_cost_factor, {0, 1000});
  p.optional("roadmap_max_vertices", c.roadmap_max_vertices, {10, 1e8});
  p.optional("roadmap_distance_min_vertices", c.roadmap_distance_min_vertices, {0, 1e8});
  p.optional("roadmap_distance_grow_time_s", c.roadmap_distance_grow_time_s, {0, 3600});
  p.optional("guide_grid", c.guide_grid);
  p.optional("goal_tolerance_m", c.goal_tolerance_m, {1e-6, 10});
  p.optional("planner_seed", c.seed);
  if (const std::string e = c.validate(); !e.empty()) p.report(e.substr(0, e.find(':')), e);
  return c;
}

ChecksConfig read_checks_config(ParamReader& p, RobotKind kind) {
  ChecksConfig c = ChecksConfig::for_kind(kind);
  constexpr Range kPositive{1e-6, 1e6};
  constexpr Range kNonNegative{0, 1e6};

  p.optional("goal_position_tolerance_m", c.goal.position_tolerance_m, kPositive);
  p.optional("goal_yaw_tolerance_deg", c.goal.yaw_tolerance_deg, {0, 180});
  p.optional("goal_check_yaw", c.goal.check_yaw);

  p.optional("c_thres_percent", c.utility.c_thres_percent, {0, 100});

  TrafficConfig& t = c.traffic;
  p.optional("traffic_d0_m", t.d0_m, kPositive);
  p.optional("traffic_k_s", t.k_s, kNonNegative);
  p.optional("traffic_margin_m", t.margin_m, kNonNegative);
  p.optional("traffic_frontal_angle_deg", t.frontal_angle_deg, {1, 89});
  p.optional("traffic_tie_time_s", t.tie_time_s, kNonNegative);
  p.optional("traffic_sample_step_m", t.sample_step_m, {0.005, 1});
  p.optional("traffic_aside_extra_m", t.aside_extra_m, kNonNegative);
  p.optional("traffic_aside_max_m", t.aside_max_m, {0, 100});
  p.optional("traffic_aside_step_m", t.aside_step_m, {0.01, 10});
  p.optional("traffic_aside_min_move_m", t.aside_min_move_m, {0, 10});
  p.optional("traffic_wait_until_out_of_view", t.wait_until_out_of_view);
  p.optional("traffic_fov_deg", t.fov_deg, {1, 360});
  p.optional("traffic_max_wait_s", t.max_wait_s, {0.1, 1e6});

  p.optional("redundancy_same_goal_m", c.redundancy.same_goal_distance_m, kNonNegative);
  p.optional("redundancy_match_cluster_ids", c.redundancy.match_cluster_ids);

  // cross-key rules the per-key ranges cannot see
  if (t.aside_max_m < t.aside_extra_m)
    p.report("traffic_aside_max_m", "must be >= traffic_aside_extra_m");
  return c;
}

}  // namespace scancrew::low_level_planner
