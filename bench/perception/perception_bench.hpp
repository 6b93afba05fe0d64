#pragma once

// `scancrew bench perception`: stereo depth and visual-inertial odometry on a recorded
// parking-lot sequence (figures: docs/perception.md).
//
//   1. record (unless --recording names one): a ground robot with a 320 x 256 camera at
//      10 Hz drives a loop around the pillars of the parking lot (waypoint_driver on the
//      ground-truth pose) until distance_m; stereo, IMU, ground-truth pose and depth go to
//      an MCAP file (.mcap), as `scancrew run` with the recorder would write it
//   2. replay the file through the cores of the stereo and vio components (their default
//      parameters), on one OpenCV thread, timing each frame; depth against the simulator's
//      ground-truth depth within the stereo component's range, odometry against the
//      ground-truth pose (ATE, RPE over rpe_segment_m), and its tracking losses per 100 m
//      of the true path
//
// A recording of a mission (several robots) is played for one robot: --robot NS keeps the
// topics under /NS/ only; a recording with several robots' stereo topics and no --robot
// is refused. The ground truth is the Odometry on a topic named pose_gt.
//
// Prints {"depth_ms", "vio_ms", "depth_median_rel_err", "depth_valid_ratio", "rpe_pct",
// "ate_m", "losses_per_100m", ...} with --json.

#include <cstdint>
#include <string>

namespace scancrew::bench {

struct PerceptionBenchOptions {
  std::string scene_path = "launch_cfg/scenes/parking_lot.yaml";
  std::string recording;  // play this .mcap instead of recording one
  std::string keep;       // keep the recording made here at this path
  std::string robot;      // play only this robot's topics (/robot/...); empty: all
  bool no_coast = false;  // the odometry with max_coast_s 0 (every failed frame a loss)
  bool vio_only = false;  // skip the stereo depth (its figures are then absent)
  double distance_m = 62.0;
  double rpe_segment_m = 10.0;
  uint32_t width = 320, height = 256;
  uint64_t seed = 1;
  bool json = false;
};

int run_perception_bench(const PerceptionBenchOptions& options);

}  // namespace scancrew::bench
