#include "components/low_level/checks_config.hpp"

#include "executors/params.hpp"

namespace scancrew::low_level {

ChecksConfig ChecksConfig::for_kind(RobotKind kind) {
  ChecksConfig c;
  c.obstacle = ObstacleCheckConfig::for_kind(kind);
  c.traffic = TrafficConfig::for_kind(kind);
  c.redundancy.planar = kind == RobotKind::kGround;
  return c;
}

std::string ChecksConfig::validate() const {
  std::string e;
  for (const std::string& part : {obstacle.validate(), traffic.validate(), redundancy.validate()})
    if (!part.empty()) e += (e.empty() ? "" : "; ") + part;
  return e;
}

ChecksConfig read_checks_config(ParamReader& p, RobotKind kind) {
  ChecksConfig c = ChecksConfig::for_kind(kind);
  constexpr Range kPositive{1e-6, 1e6};
  constexpr Range kNonNegative{0, 1e6};

  p.optional("goal_position_tolerance_m", c.goal.position_tolerance_m, kPositive);
  p.optional("goal_yaw_tolerance_deg", c.goal.yaw_tolerance_deg, {0, 180});
  p.optional("goal_check_yaw", c.goal.check_yaw);

  p.optional("c_thres_percent", c.utility.c_thres_percent, {0, 100});

  p.optional("safety_radius_m", c.obstacle.sphere_radius_m, kPositive);
  p.optional("safety_semi_major_m", c.obstacle.semi_major_m, kPositive);
  p.optional("safety_semi_minor_m", c.obstacle.semi_minor_m, kPositive);
  p.optional("safety_min_height_m", c.obstacle.min_height_m, {-100, 100});
  p.optional("safety_max_height_m", c.obstacle.max_height_m, {-100, 100});

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
  if (kind == RobotKind::kGround && c.obstacle.semi_major_m < c.obstacle.semi_minor_m)
    p.report("safety_semi_major_m", "must be >= safety_semi_minor_m");
  if (kind == RobotKind::kGround && c.obstacle.max_height_m <= c.obstacle.min_height_m)
    p.report("safety_max_height_m", "must be > safety_min_height_m");
  if (t.aside_max_m < t.aside_extra_m)
    p.report("traffic_aside_max_m", "must be >= traffic_aside_extra_m");
  return c;
}

}  // namespace scancrew::low_level
