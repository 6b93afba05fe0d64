#pragma once

// The rest of a local path against a newer map. With unknown_is_occupied false (the
// parking-lot files: paths may cross unknown space) a path planned through space the map
// did not know yet is not checked again by LazyPRM*: the low-level planner re-checks the
// part ahead of the robot when a new snapshot comes, and plans again when it is blocked.
// Not in the thesis, whose ObstacleCheck alone guards a path between plans; its safety
// volume (0.55 x 0.25 m, table 5.3) reaches only ~0.05 m past the ground robot's corners
// across the heading, so a robot driving at a shallow angle at a wall it had not mapped
// when it planned touched it before the check fired (docs/low_level_planner.md, "Path
// re-check").
//
// Pure functions; the map comes in as a callable. No allocation. Any thread.

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <span>

#include "interfaces/nav_msgs.hpp"

namespace scancrew::motion {

// The index of the first waypoint ahead of `position` on `path`: the end of the segment
// nearest to it (0 for a path of one waypoint, or an empty one).
size_t first_waypoint_ahead(std::span<const msg::Waypoint> path, const Eigen::Vector3d& position);

struct PathRecheck {
  bool blocked = false;
  double blocked_at_m = 0;  // arc length from the robot's projection on the path
  Eigen::Vector3d where = Eigen::Vector3d::Zero();  // the first pose found in collision
  size_t poses_checked = 0;
};

// Samples `path` from the point nearest `position` (on the segment nearest it) onward,
// every `step_m` (> 0) and at each waypoint, up to `horizon_m` of arc length, with the yaw
// interpolated the short way between waypoints; the first pose `is_free` refuses blocks the
// path. The robot's own pose is not checked: ObstacleCheck watches it, and a robot driving
// close to a surface within the planner's margin should not replan for that alone.
PathRecheck recheck_path(std::span<const msg::Waypoint> path, const Eigen::Vector3d& position,
                         double horizon_m, double step_m,
                         const std::function<bool(const msg::Waypoint&)>& is_free);

}  // namespace scancrew::motion
