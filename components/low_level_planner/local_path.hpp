#pragma once

// The local path sent to the tracker, as the low-level planner reads it back: what is left of
// it ahead of the robot (the traffic policy's view) and its length. Pure functions.

#include <Eigen/Core>
#include <vector>

#include "interfaces/nav_msgs.hpp"

namespace scancrew::low_level_planner {

// The rest of a local path for the traffic policy: the waypoints after the segment nearest
// to the robot (it is somewhere along that segment), goal last. Not from the nearest
// waypoint: on a long straight path that is the start, behind the robot, and the policy's
// path cut at the safety distance would then only hold the way back.
std::vector<Eigen::Vector3d> remaining_path(const std::vector<msg::Waypoint>& path,
                                            const Eigen::Vector3d& position);

// The length of the path from `start` through its waypoints (m).
double path_length_m(const msg::Vec3& start, const std::vector<msg::Waypoint>& path);

}  // namespace scancrew::low_level_planner
