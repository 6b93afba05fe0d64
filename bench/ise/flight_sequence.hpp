#pragma once

// A multirotor's depth images around a large open-air scene (the powerplant of thesis
// 2.6.1), for `scancrew bench ise`; the flying sibling of bench/tsdf/depth_sequence.hpp.
// The frames are handed to a sink as they are rendered, not kept: a dense lap is more
// frames than memory should hold.
//
// The multirotor (camera of table 2.1: range [1.6, 8] m, baseline 0.11 m, 90° × 60° FOV,
// at the body centre) starts at the scene bounds' (max x, min y) corner at `altitude_m` and
// flies, without rendering, to the first corner of a rectangle `standoff_m` outside the
// target footprint; then it flies that rectangle once (or lap_fraction of it), counter-clockwise,
// at `speed_mps`, turning its camera towards the nearest point of the footprint (the
// waypoint_driver's multirotor law to reach the lap, then a reference point moving along it
// at `speed_mps`; a yaw law of our own for the heading), and renders one noisy depth image
// (thesis 2.6.1 noise model) every perimeter × lap_fraction / frames metres. Physics and noise are
// seeded: the same options give the same frames.

#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include "core/result.hpp"
#include "interfaces/sensor_msgs.hpp"
#include "sim/scene.hpp"

namespace scancrew::bench {

struct FlightSequenceOptions {
  // 752 × 434: 90° × 60° with square pixels and f = 376 px, the thesis's (table 2.1)
  uint32_t width = 752, height = 434;
  int frames = 1000;          // over lap_fraction of the lap
  double lap_fraction = 1.0;  // (0, 1]: the frames' spacing stays that of a whole lap's
  // the footprint to fly around (x and y, min then max) and the lap's distance from it;
  // the default: the powerplant's outer walls and row of stacks between 1 and 5 m above
  // the ground (launch_cfg/scenes/powerplant.yaml, measured on its `scancrew groundtruth`
  // points; the upper storeys are set back)
  std::array<double, 4> footprint_m = {-33.0, -21.0, 33.0, 20.0};
  double standoff_m = 5.0;
  // the altitude swings between mean ± swing (a sine over swing_period_m of the lap), so
  // the plant is seen from 2 to 12 m
  double altitude_m = 7.0;
  double altitude_swing_m = 5.0;
  double swing_period_m = 24.0;
  double speed_mps = 2.0;
  double min_range_m = 1.6;
  double max_range_m = 8.0;
  uint64_t seed = 1;  // depth noise
};

struct FlightSummary {
  msg::CameraIntrinsics intrinsics;
  int frames = 0;
  double flown_m = 0;  // along the lap, at the last frame
  double sim_s = 0;
  double render_s = 0;  // wall time in rendering and the noise model
  double wall_s = 0;    // the whole flight, the sink's time included
};

// Called with each frame (noisy depth, NaN outside the range; T_world_cam set); an error
// ends the flight with it.
using FrameSink = std::function<Result<void, std::string>(const msg::DepthImage& depth)>;

// Flies the lap; progress on stderr. Fails when the simulator cannot be made (no GL, a
// start outside the scene bounds), a render fails or the sink fails.
Result<FlightSummary, std::string> fly_lap(const sim::SceneSpec& scene,
                                           const FlightSequenceOptions& options,
                                           const FrameSink& sink);

}  // namespace scancrew::bench
