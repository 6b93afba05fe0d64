#include "core/motion/map_queries.hpp"

#include <utility>

#include "core/motion/obstacle_check.hpp"
#include "core/tsdf/tsdf_map.hpp"

namespace scancrew::motion {

OccupancyQuery occupancy_query(std::shared_ptr<const tsdf::MapSnapshot> map) {
  if (!map) return {};
  return [map = std::move(map)](const Eigen::Vector3d& p) {
    return map->state_at(p) == tsdf::VoxelState::kOccupied;
  };
}

FreeSpaceQuery free_space_query(std::shared_ptr<const tsdf::MapSnapshot> map,
                                const FreeSpaceSpec& spec) {
  if (!map) return {};
  // the body's volume as an ObstacleCheck volume: a disc (ellipse with equal axes) or a ball
  ObstacleCheckConfig volume = ObstacleCheckConfig::for_kind(spec.kind);
  volume.sphere_radius_m = spec.body_radius_m;
  volume.semi_major_m = spec.body_radius_m;
  volume.semi_minor_m = spec.body_radius_m;
  volume.min_height_m = spec.min_height_m;
  volume.max_height_m = spec.max_height_m;
  OccupancyQuery occupied = occupancy_query(map);
  return [map = std::move(map), spec, volume,
          occupied = std::move(occupied)](const Eigen::Vector3d& p) {
    const ObstacleCheckResult r = obstacle_check(p, 0.0, map->voxel_m(), occupied, volume);
    if (r.stop()) return false;
    if (spec.unknown_is_free) return true;
    Eigen::Vector3d centre = p;
    if (spec.kind == RobotKind::kGround)
      centre.z() += 0.5 * (spec.min_height_m + spec.max_height_m);
    return map->state_at(centre) == tsdf::VoxelState::kEmpty;
  };
}

}  // namespace scancrew::motion
