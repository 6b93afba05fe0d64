#pragma once

// `scancrew render <scene.yaml> --out DIR`: what the simulator builds, as pictures —
// left, right and depth images from a robot's stereo camera, and a view from above.

#include <optional>
#include <string>
#include <vector>

#include "core/robot/robot_kind.hpp"

namespace scancrew::cli {

struct RenderOptions {
  std::string scene_path;
  std::string out_dir;
  std::vector<double> pose;  // x, y, yaw_deg; empty: a free corner facing the centre
  robot::RobotKind kind = robot::RobotKind::kGround;
  double z_m = 1.5;  // multirotor altitude
  unsigned width = 640, height = 370;
};

int run_render(const RenderOptions& options);

}  // namespace scancrew::cli
