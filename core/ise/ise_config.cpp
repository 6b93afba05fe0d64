#include "core/ise/ise_config.hpp"

#include <cmath>

namespace scancrew::ise {

std::string IseConfig::validate(double w_th, double voxel_m) const {
  std::string out;
  auto problem = [&](const std::string& p) { out += (out.empty() ? "" : "; ") + p; };
  if (!(w_th > 0 && std::isfinite(w_th))) problem("W_th must be positive");
  if (!(voxel_m > 0 && std::isfinite(voxel_m))) problem("voxel size must be positive");
  if (robot_types.empty()) problem("no robot type");
  uint32_t seen = 0;
  for (const RobotTypeSpec& t : robot_types) {
    const std::string name = to_string(t.type);
    if ((seen & robot::kind_bit(t.type)) != 0) problem(name + " listed twice");
    seen |= robot::kind_bit(t.type);
    if (!(t.min_range_m > 0 && t.max_range_m > t.min_range_m))
      problem(name + ": camera range must satisfy 0 < min < max");
    if (!(t.delta_pose_m >= t.min_range_m && t.delta_pose_m <= t.max_range_m))
      problem(name + ": delta_pose_m " + std::to_string(t.delta_pose_m) +
              " is outside the camera range [" + std::to_string(t.min_range_m) + ", " +
              std::to_string(t.max_range_m) + "]");
    if (!(t.fov_h_deg > 0 && t.fov_h_deg < 180 && t.fov_v_deg > 0 && t.fov_v_deg < 180))
      problem(name + ": FOV must be in (0, 180) degrees");
    if (!(t.clearance_m >= 0)) problem(name + ": clearance_m must be >= 0");
    if (std::isnan(t.min_altitude_m) || std::isnan(t.max_altitude_m) ||
        !(t.min_altitude_m < t.max_altitude_m))
      problem(name + ": min_altitude_m must be below max_altitude_m");
    if (t.type == RobotKind::kGround &&
        !(t.camera_height_m > 0 && t.body_height_m > 0 && std::isfinite(t.floor_z_m)))
      problem(name + ": camera_height_m and body_height_m must be positive");
  }
  if (!(merge_distance_m >= 0)) problem("merge_distance_m must be >= 0");
  if (!(merge_angle_deg >= 0 && merge_angle_deg < 90))
    problem("merge_angle_deg must be in [0, 90)");
  if (!(d_v_m > 0)) problem("d_v_m must be positive");
  if (!(d_v_max_m >= d_v_m))
    problem("d_v_m " + std::to_string(d_v_m) + " is greater than d_v_max_m " +
            std::to_string(d_v_max_m));
  if (gain_rows < 1 || gain_cols < 1 || gain_rows > 1000 || gain_cols > 1000)
    problem("gain_rows and gain_cols must be in [1, 1000]");
  if (completion_updates < 1) problem("completion_updates must be >= 1");
  if (region_min_m.hasNaN() || region_max_m.hasNaN() ||
      !(region_min_m.array() < region_max_m.array()).all())
    problem("region_min_m must be below region_max_m on every axis");
  return out;
}

}  // namespace scancrew::ise
