#pragma once

// The planner bench's query ends (planner_bench.hpp): the robot's own poses that are free in
// the final map, topped up with random free positions in the map's box, drawn in pairs.

#include <cstddef>
#include <random>
#include <utility>
#include <vector>

#include "core/motion/motion_planner.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::bench {

// Every other pose in `poses` that is free for `planner` (a multirotor's only inside its
// altitude band).
std::vector<msg::Waypoint> free_robot_poses(const std::vector<msg::Waypoint>& poses,
                                            const motion::PlannerConfig& config,
                                            const motion::MotionPlanner& planner);

// Appends random positions (random yaw) in the map's box that are free for `planner` until
// `free` holds up_to poses or 200000 draws were made; a ground robot's on the floor.
void add_random_free_positions(const tsdf::MapSnapshot& map, const motion::PlannerConfig& config,
                               const motion::MotionPlanner& planner, size_t up_to,
                               std::mt19937_64& rng, std::vector<msg::Waypoint>& free);

// Up to `count` pairs of poses from `free` at least min_distance_m apart (100000 draws at
// most); none when `free` holds fewer than two.
std::vector<std::pair<msg::Waypoint, msg::Waypoint>> draw_query_pairs(
    const std::vector<msg::Waypoint>& free, size_t count, double min_distance_m,
    std::mt19937_64& rng);

}  // namespace scancrew::bench
