#pragma once

// The input of `scancrew bench tsdf`: a fixed, deterministic sequence of noisy depth images
// with their ground-truth camera poses, rendered with the team simulator directly.
//
// A ground robot (default camera mount: 0.35 m above the floor, 0.26 m baseline) drives
// the loop around the parking lot's three pillars that `scancrew bench perception` uses,
// with the waypoint_driver's control law (components/waypoint_driver) on its ground-truth
// pose, at 0.5 m/s; every frame_period_s of sim time its left camera's depth is rendered
// and the depth noise model of thesis 2.6.1 applied (the simulator's default, over
// [min_range, max_range]). Physics and noise are seeded, so the same options give the same
// frames and, for any resolution, the same poses.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "core/tsdf/integrator.hpp"
#include "interfaces/geometry.hpp"
#include "sim/robot_model.hpp"
#include "sim/scene.hpp"
#include "sim/team_sim.hpp"

namespace scancrew::bench {

struct DepthSequenceOptions {
  uint32_t width = 320, height = 256;  // 90° horizontal FOV, square pixels
  int frames = 60;
  double frame_period_s = 1.5;  // sim time between frames (0.75 m of straight driving)
  double min_range_m = 0.3;     // the depth sensor's range: NaN outside
  double max_range_m = 8.0;
  uint64_t seed = 1;  // depth noise
};

struct DepthSequence {
  msg::CameraIntrinsics intrinsics;
  double min_range_m = 0, max_range_m = 0;
  std::vector<std::vector<float>> depth_m;  // per frame, row-major; NaN = no measurement
  std::vector<msg::Pose3> T_world_cam;      // per frame, optical frame (z forward, y down)
  double driven_m = 0;                      // the robot's odometer (ground truth)
  double sim_s = 0;
  double wall_s = 0;
};

// The simulator for a benchmark's one robot, its camera set to width × height with a 90°
// horizontal FOV and square pixels (vertical FOV 2·atan(h/w)) over [min_range, max_range]:
// shared by this sequence and bench/ise's flight. Fails on a bad camera or simulator.
Result<std::unique_ptr<sim::TeamSim>, std::string> make_camera_sim(
    const sim::SceneSpec& scene, sim::RobotSpec robot, uint32_t width, uint32_t height,
    double min_range_m, double max_range_m, uint64_t seed);

// Renders the sequence; progress on stderr. Fails when the simulator cannot be made (no
// GL, a robot start inside an obstacle) or a render fails.
Result<DepthSequence, std::string> render_depth_sequence(const sim::SceneSpec& scene,
                                                         const DepthSequenceOptions& options);

// One depth image as the integrator takes it (a view: `depth_m` must outlive the frame).
tsdf::DepthFrame depth_frame(const std::vector<float>& depth_m, const msg::CameraIntrinsics& k,
                             const msg::Pose3& T_world_cam);

}  // namespace scancrew::bench
