#include "components/low_level/planner_config.hpp"

#include <cmath>
#include <vector>

namespace scancrew::low_level {

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

PlannerConfig read_planner_config(ParamReader& p) {
  PlannerConfig c;
  std::string type = "ground";
  p.choice("robot_type", type, {"ground", "multirotor"});
  c.robot_kind = type == "multirotor" ? RobotKind::kMultirotor : RobotKind::kGround;
  Eigen::Vector3d& ground_radii = c.ground_body.safety_radii_m;
  std::vector<double> radii(ground_radii.data(), ground_radii.data() + 3);
  p.optional_list("ground_body_radii_m", radii, 3, {1e-3, 100});
  if (radii.size() == 3) ground_radii = Eigen::Vector3d(radii[0], radii[1], radii[2]);
  p.optional("ground_body_center_z_m", c.ground_body.safety_center_z_m, {-1e4, 1e4});
  double multirotor_radius = c.multirotor_body.safety_radii_m.x();
  p.optional("multirotor_body_radius_m", multirotor_radius, {1e-3, 100});
  c.multirotor_body.safety_radii_m.setConstant(multirotor_radius);
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

}  // namespace scancrew::low_level
