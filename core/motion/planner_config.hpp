#pragma once

// Parameters of the low-level planner's core (thesis 2.5.3, Algorithm 1, 3.5.2, 4.5.2;
// tables 2.1 and 5.3); low_level_planner::read_planner_config() reads them from a
// component's launch parameters. Defaults: the thesis's where it gives one (bodies), else ours
// (docs/low_level_planner.md lists which).

#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "core/motion/check_types.hpp"  // RobotKind
#include "core/robot/body_model.hpp"

namespace scancrew::motion {

struct PlannerConfig {
  // key robot_type: ground (SE(2), z fixed) | multirotor (x, y, z, yaw)
  robot::RobotKind robot_kind = robot::RobotKind::kGround;

  // --- body (thesis 2.5.3: ellipsoid for ground robots, sphere for multirotors) ---
  // each kind's BodyModel (core/robot/body_model.hpp); keys ground_body_radii_m [3] and
  // ground_body_center_z_m set the ground body's safety volume, multirotor_body_radius_m the
  // multirotor's sphere
  robot::BodyModel ground_body = robot::BodyModel::of(robot::RobotKind::kGround);
  robot::BodyModel multirotor_body = robot::BodyModel::of(robot::RobotKind::kMultirotor);
  // added to every semi-axis: an occupied voxel's box may start up to half a voxel
  // behind the true surface, so the margin keeps paths clear of the real geometry
  double body_margin_m = 0.1;

  // --- map ---
  // unknown voxels (and never-observed blocks) collide like occupied ones
  bool unknown_is_occupied = true;
  // a snapshot stamped more than this before the robot's pose is stale (kMapStale)
  double max_map_age_s = 2.0;

  // --- state space ---
  // the sampling bounds: the observed blocks' box (grown to hold start and goal) plus this
  double bounds_margin_m = 2.0;
  // multirotor altitude limits (body centre), intersected with the bounds
  double multirotor_min_altitude_m = 1.0;
  double multirotor_max_altitude_m = 100.0;

  // --- LazyPRM* (Hauser 2015, through OMPL) ---
  double planner_time_limit_s = 1.0;    // per query (thesis 2.6.1: "below 1 s" on average)
  double collision_check_step_m = 0.1;  // between the states checked along a motion
  // 0: stop at the first path found on the roadmap (A* over it: the roadmap's shortest);
  // > 0: keep growing the roadmap until a path no longer than factor × the straight-line
  // distance is found, or the time limit
  double path_cost_factor = 0.0;
  // the roadmap is dropped and rebuilt when it holds more vertices than this
  int64_t roadmap_max_vertices = 20000;
  // roadmap_distances() (the high-level planner's d(τ_kl)): before the search, a roadmap
  // with fewer vertices than this is grown (LazyPRM*'s samples, edges unchecked) for at
  // most roadmap_distance_grow_time_s (capped at roadmap_max_vertices; 0: never grown,
  // only plan() grows it)
  int64_t roadmap_distance_min_vertices = 500;
  double roadmap_distance_grow_time_s = 0.25;
  // ground robots with unknown_is_occupied: before LazyPRM* searches, poses along a 2D grid
  // path through the map's body-height layer are added to the roadmap (guided sampling,
  // guide_path.hpp)
  bool guide_grid = true;
  double goal_tolerance_m = 1e-3;  // the state-space distance at which the goal is reached
  // OMPL's random seed (process wide, taken once, before the first planner); 0: OMPL's own
  uint64_t seed = 0;

  // Empty when valid, else what is wrong (names the key).
  std::string validate() const;
};

// The body the config describes, the margin added.
robot::BodyModel body_of(const PlannerConfig& config);

}  // namespace scancrew::motion
