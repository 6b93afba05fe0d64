#include "core/motion/planner_config.hpp"

#include <cmath>
#include <vector>

namespace scancrew::motion {

std::string PlannerConfig::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  for (int i = 0; i < 3; ++i)
    if (!positive(ground_body.safety_radii_m[i])) return "ground_body_radii_m: must be > 0";
  if (!std::isfinite(ground_body.safety_center_z_m))
    return "ground_body_center_z_m: must be finite";
  for (int i = 0; i < 3; ++i)
    if (!positive(multirotor_body.safety_radii_m[i]))
      return "multirotor_body_radius_m: must be > 0";
  if (!std::isfinite(body_margin_m) || body_margin_m < 0) return "body_margin_m: must be >= 0";
  if (!std::isfinite(max_map_age_s) || max_map_age_s < 0) return "max_map_age_s: must be >= 0";
  if (!std::isfinite(bounds_margin_m) || bounds_margin_m < 0)
    return "bounds_margin_m: must be >= 0";
  if (!std::isfinite(multirotor_min_altitude_m) || !std::isfinite(multirotor_max_altitude_m) ||
      multirotor_min_altitude_m >= multirotor_max_altitude_m)
    return "multirotor_min_altitude_m, multirotor_max_altitude_m: need min < max";
  if (!positive(planner_time_limit_s)) return "planner_time_limit_s: must be > 0";
  if (!positive(collision_check_step_m)) return "collision_check_step_m: must be > 0";
  if (!std::isfinite(path_cost_factor) || (path_cost_factor != 0 && path_cost_factor < 1))
    return "path_cost_factor: 0 (first path) or >= 1";
  if (roadmap_max_vertices < 10) return "roadmap_max_vertices: must be >= 10";
  if (roadmap_distance_min_vertices < 0) return "roadmap_distance_min_vertices: must be >= 0";
  if (!std::isfinite(roadmap_distance_grow_time_s) || roadmap_distance_grow_time_s < 0)
    return "roadmap_distance_grow_time_s: must be >= 0";
  if (!positive(goal_tolerance_m)) return "goal_tolerance_m: must be > 0";
  return {};
}

robot::BodyModel body_of(const PlannerConfig& c) {
  return (c.robot_kind == RobotKind::kGround ? c.ground_body : c.multirotor_body)
      .inflated(c.body_margin_m);
}

}  // namespace scancrew::motion
