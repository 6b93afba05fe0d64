#include "components/low_level_planner/planner_params.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace scancrew::low_level_planner {

using motion::TrafficConfig;

PlannerConfig read_planner_config(ParamReader& p) {
  PlannerConfig c;
  p.choice("robot_type", c.robot_kind, robot::kRobotKindNames)
      .doc("ground (SE(2), z fixed) or multirotor (x, y, z, yaw)");
  p.optional("body_margin_m", c.body_margin_m, {0, 10})
      .doc("added to every semi-axis of the body: keeps paths clear of the real surface (m)");
  p.optional("unknown_is_occupied", c.unknown_is_occupied)
      .doc("unknown voxels (and never-observed blocks) collide like occupied ones");
  p.optional("max_map_age_s", c.max_map_age_s, {0, 1e6})
      .doc("a map stamped more than this before the robot's pose is stale (s)");
  p.optional("bounds_margin_m", c.bounds_margin_m, {0, 1000})
      .doc(
          "sampling bounds: the observed blocks' box (grown to hold start and goal) plus this (m)");
  p.optional("multirotor_min_altitude_m", c.multirotor_min_altitude_m, {-1e4, 1e4})
      .doc("multirotor altitude limit, bottom (body centre, m)");
  p.optional("multirotor_max_altitude_m", c.multirotor_max_altitude_m, {-1e4, 1e4})
      .doc("multirotor altitude limit, top (body centre, m)");
  p.optional("planner_time_limit_s", c.planner_time_limit_s, {1e-3, 3600})
      .doc("LazyPRM* time per query (s)");
  p.optional("collision_check_step_m", c.collision_check_step_m, {1e-3, 10})
      .doc("distance between the states checked along a motion (m)");
  p.optional("path_cost_factor", c.path_cost_factor, {0, 1000})
      .doc(
          "0: the first path found on the roadmap; > 0: grow until a path within factor × the "
          "straight line, or the time limit");
  p.optional("roadmap_max_vertices", c.roadmap_max_vertices, {10, 1e8})
      .doc("the roadmap is dropped and rebuilt when it holds more vertices than this");
  p.optional("roadmap_distance_min_vertices", c.roadmap_distance_min_vertices, {0, 1e8})
      .doc("roadmap_distances() first grows a roadmap with fewer vertices than this (0: never)");
  p.optional("roadmap_distance_grow_time_s", c.roadmap_distance_grow_time_s, {0, 3600})
      .doc("the bound on that growth, per call (s)");
  p.optional("guide_grid", c.guide_grid)
      .doc(
          "ground robots with unknown_is_occupied: add poses along a 2D grid path to the roadmap "
          "(guided sampling)");
  p.optional("goal_tolerance_m", c.goal_tolerance_m, {1e-6, 10})
      .doc("the state-space distance at which the goal is reached");
  p.optional("planner_seed", c.seed)
      .doc("OMPL's random seed (process wide, taken once; 0: OMPL's own)");
  if (const std::string e = c.validate(); !e.empty()) p.report(e.substr(0, e.find(':')), e);
  return c;
}

ChecksConfig read_checks_config(ParamReader& p, RobotKind kind) {
  ChecksConfig c = ChecksConfig::for_kind(kind);
  constexpr Range kPositive{1e-6, 1e6};
  constexpr Range kNonNegative{0, 1e6};

  p.optional("goal_position_tolerance_m", c.goal.position_tolerance_m, kPositive)
      .doc("GoalReached: position tolerance (m; planar for ground robots)");
  p.optional("goal_yaw_tolerance_deg", c.goal.yaw_tolerance_deg, {0, 180})
      .doc("GoalReached: yaw tolerance (degrees; ignored when goal_check_yaw is false)");
  p.optional("goal_check_yaw", c.goal.check_yaw).doc("GoalReached also checks the yaw");

  p.optional("c_thres_percent", c.utility.c_thres_percent, {0, 100})
      .doc("UtilityCheck: threshold C_thres (%; tables 2.1, 3.1, 4.1)");

  TrafficConfig& t = c.traffic;
  p.optional("traffic_d0_m", t.d0_m, kPositive)
      .doc("safety distance d = d0 + k·v: d0 (m; ground 0.55, multirotor 1.0)");
  p.optional("traffic_k_s", t.k_s, kNonNegative).doc("safety distance d = d0 + k·v: k (s)");
  p.optional("traffic_margin_m", t.margin_m, kNonNegative).doc("gap kept between bodies (m)");
  p.optional("traffic_frontal_angle_deg", t.frontal_angle_deg, {1, 89})
      .doc("within this of opposite: frontal; of parallel: following (degrees)");
  p.optional("traffic_tie_time_s", t.tie_time_s, kNonNegative)
      .doc("arrival times closer than this: the lower id proceeds (s)");
  p.optional("traffic_sample_step_m", t.sample_step_m, {0.005, 1})
      .doc("path sampling for conflicts and aside segments (m)");
  p.optional("traffic_aside_extra_m", t.aside_extra_m, kNonNegative)
      .doc("aside points from clearance + this (m)");
  p.optional("traffic_aside_max_m", t.aside_max_m, {0, 100}).doc("out to clearance + this (m)");
  p.optional("traffic_aside_step_m", t.aside_step_m, {0.01, 10}).doc("in steps of this (m)");
  p.optional("traffic_aside_min_move_m", t.aside_min_move_m, {0, 10})
      .doc("no aside point nearer the robot than this (m)");
  p.optional("traffic_wait_until_out_of_view", t.wait_until_out_of_view)
      .doc("after a crossing, wait until the teammate leaves the field of view (or is far enough)");
  p.optional("traffic_fov_deg", t.fov_deg, {1, 360})
      .doc("horizontal camera FOV for that wait (degrees; table 5.3)");
  p.optional("traffic_max_wait_s", t.max_wait_s, {0.1, 1e6})
      .doc("a longer hold asks for re-planning (s)");

  p.optional("redundancy_same_goal_m", c.redundancy.same_goal_distance_m, kNonNegative)
      .doc(
          "RedundancyCheck: two tour stops are the same cluster when their goals are this close "
          "(m)");
  p.optional("redundancy_match_cluster_ids", c.redundancy.match_cluster_ids)
      .doc("RedundancyCheck: also match stops with equal cluster ids (a shared map)");

  // cross-key rules the per-key ranges cannot see
  if (t.aside_max_m < t.aside_extra_m)
    p.report("traffic_aside_max_m", "must be >= traffic_aside_extra_m");
  return c;
}

}  // namespace scancrew::low_level_planner
