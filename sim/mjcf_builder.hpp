#pragma once

// build_mjcf(): a scene and a team -> the MJCF text MuJoCo loads. Each robot is a body on
// slide joints (x, y; z for multirotors) and a yaw hinge, driven by velocity actuators;
// its stereo pair is two fixed cameras. Names follow "<robot>_x", "<robot>_left", ...
// The ceiling is in geom group 1, so views from above can hide it. Gravity is off: robots are
// velocity-controlled kinematic bodies (the IMU model adds gravity back analytically), so a
// multirotor holds its altitude without a controller.

#include <string>
#include <vector>

#include "sim/robot_model.hpp"
#include "sim/scene.hpp"

namespace scancrew::sim {

struct MjcfOptions {
  double timestep_s = 0.005;
  uint32_t offscreen_width = 640, offscreen_height = 480;  // >= every camera
  double velocity_response =
      0.5;  // share of the velocity error an actuator removes per step (0, 1]
  // The placed, textured OBJ of each scene.meshes entry (write_textured_obj), in order.
  std::vector<std::string> mesh_files;
};

// One repeat of the random-dot texture covers this length (1024 dots).
double texture_period_m(const SceneSpec& scene);

// options.mesh_files must hold one file per scene mesh (std::out_of_range otherwise).
std::string build_mjcf(const SceneSpec& scene, const std::vector<RobotSpec>& robots,
                       const MjcfOptions& options);

// Names of the generated elements, shared by the builder and the simulator.
std::string joint_name(const RobotSpec& robot, const char* axis);  // axis: "x", "y", "z", "yaw"
std::string camera_name(const RobotSpec& robot, bool left);
std::string body_name(const RobotSpec& robot);
// The camera's height above the body frame origin.
double camera_height_m(const RobotSpec& robot);

}  // namespace scancrew::sim
