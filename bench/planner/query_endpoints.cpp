#include "bench/planner/query_endpoints.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/tsdf/block.hpp"

namespace scancrew::bench {

std::vector<msg::Waypoint> free_robot_poses(const std::vector<msg::Waypoint>& poses,
                                            const motion::PlannerConfig& config,
                                            const motion::MotionPlanner& planner) {
  std::vector<msg::Waypoint> free;
  for (size_t i = 0; i < poses.size(); i += 2) {
    const msg::Waypoint& p = poses[i];
    const bool in_band = config.robot_kind == robot::RobotKind::kGround ||
                         (p.position.z > config.multirotor_min_altitude_m &&
                          p.position.z < config.multirotor_max_altitude_m);
    if (!in_band || !planner.is_free(p)) continue;
    free.push_back(p);
  }
  return free;
}

void add_random_free_positions(const tsdf::MapSnapshot& map, const motion::PlannerConfig& config,
                               const motion::MotionPlanner& planner, size_t up_to,
                               std::mt19937_64& rng, std::vector<msg::Waypoint>& free) {
  Eigen::AlignedBox3d box;
  const double block_m = map.voxel_m() * tsdf::kBlockSide;
  for (const auto& [index, block] : map.blocks()) {
    box.extend(index.cast<double>() * block_m);
    box.extend((index + Eigen::Vector3i::Ones()).cast<double>() * block_m);
  }
  std::uniform_real_distribution<double> u(0, 1), yaw(-M_PI, M_PI);
  for (int tries = 0; free.size() < up_to && tries < 200000; ++tries) {
    msg::Waypoint w;
    w.position = {box.min().x() + u(rng) * box.sizes().x(),
                  box.min().y() + u(rng) * box.sizes().y(),
                  std::clamp(box.min().z() + u(rng) * box.sizes().z(),
                             config.multirotor_min_altitude_m + 0.01,
                             config.multirotor_max_altitude_m - 0.01)};
    if (config.robot_kind == robot::RobotKind::kGround) w.position.z = 0;
    w.yaw_rad = yaw(rng);
    if (planner.is_free(w)) free.push_back(w);
  }
}

std::vector<std::pair<msg::Waypoint, msg::Waypoint>> draw_query_pairs(
    const std::vector<msg::Waypoint>& free, size_t count, double min_distance_m,
    std::mt19937_64& rng) {
  std::vector<std::pair<msg::Waypoint, msg::Waypoint>> pairs;
  if (free.size() >= 2) {
    std::uniform_int_distribution<size_t> pick(0, free.size() - 1);
    for (int tries = 0; pairs.size() < count && tries < 100000; ++tries) {
      const msg::Waypoint& a = free[pick(rng)];
      const msg::Waypoint& b = free[pick(rng)];
      const double d = std::hypot(a.position.x - b.position.x, a.position.y - b.position.y,
                                  a.position.z - b.position.z);
      if (d >= min_distance_m) pairs.emplace_back(a, b);
    }
  }
  return pairs;
}

}  // namespace scancrew::bench
