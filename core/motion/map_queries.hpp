#pragma once

// Adapters from the TSDF map (core/tsdf/tsdf_map.hpp) to the callables the checks
// take (check_types.hpp): occupancy for ObstacleCheck, free space for the traffic policy's
// aside point. Kept out of the checks' library so that they stay independent of the map
// type (library scancrew_low_level_checks_tsdf).
//
// The callables hold the snapshot (shared ownership) and read it only: thread safe as the
// snapshot is (immutable).

#include <memory>

#include "core/motion/check_types.hpp"

namespace scancrew::tsdf {
class MapSnapshot;
}

namespace scancrew::motion {

// Occupied: the voxel holding the point is known and φ ≤ 0.
OccupancyQuery occupancy_query(std::shared_ptr<const tsdf::MapSnapshot> map);

// The body fits at the point: no occupied voxel centre within `body_radius_m` (planar disc
// between min_height_m and max_height_m above the point for ground robots, a ball for
// aerial ones), and, unless `unknown_is_free`, the point's own voxel is known and empty.
struct FreeSpaceSpec {
  RobotKind kind = RobotKind::kGround;
  double body_radius_m = 0.3;
  double min_height_m = 0.1;  // ground: as ObstacleCheckConfig
  double max_height_m = 0.5;
  bool unknown_is_free = false;
};
FreeSpaceQuery free_space_query(std::shared_ptr<const tsdf::MapSnapshot> map,
                                const FreeSpaceSpec& spec);

}  // namespace scancrew::motion
