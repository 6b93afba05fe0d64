#pragma once

// The ground robot's loop around the parking lot's three pillars, as the perception bench
// (which records it) and the pipeline bench (which captures stereo pairs on it) launch it.

#include <cstdint>
#include <string>

namespace scancrew::bench {

// The loop's waypoints as waypoint_driver's waypoints_m takes them (x, y, z in metres; 37.2
// m from the start at (-7.5, -1.8)): 1.8 m either side of the pillars, 3 m clear of the end
// walls, every obstacle of the scene at least 0.9 m from the path.
inline constexpr const char* kParkingLotLoop =
    "[7.5, -1.8, 0, 7.5, 1.8, 0, -7.5, 1.8, 0, -7.5, -1.8, 0]";

// The head of a launch file that drives one ground robot around the loop on sim time (step
// executor, 0.05 s steps, `duration_s` at most): the robot `robot_ns` at the loop's start,
// its pose remapped to the ground truth, and the team simulator on `scene_path` (seeded)
// with no depth topic and the ground camera at width × height pixels (square, 90°
// horizontally). The text ends inside the simulator's params, at six spaces' indent: the
// caller appends more params, then its components (two spaces' indent). Allocates.
std::string parking_lot_loop_launch(double duration_s, const std::string& robot_ns,
                                    const std::string& scene_path, uint64_t seed, uint32_t width,
                                    uint32_t height);

}  // namespace scancrew::bench
