#pragma once

// Tiny inline scenes and robots for the simulator tests.

#include <gtest/gtest.h>

#include "sim/scene.hpp"
#include "sim/team_sim.hpp"

namespace scancrew::sim::test {

// A 10 x 10 x 3 m room, no walls, and one wall-like box whose front face is the plane
// x = 2.9 m.
inline SceneSpec wall_scene() {
  auto scene = parse_scene(R"(
name: wall
bounds_min_m: [-5, -5, 0]
bounds_max_m: [5, 5, 3]
boxes:
  - {name: wall, center_m: [3.0, 0, 1.5], size_m: [0.2, 8, 3]}
)",
                           "wall.yaml", ".");
  EXPECT_TRUE(scene) << (scene ? "" : scene.error().front());
  return *scene;
}

inline RobotSpec ground_robot(const std::string& name, double x, double y, double yaw = 0) {
  RobotSpec r;
  r.id = 1;
  r.name = name;
  r.kind = RobotKind::kGround;
  r.start_x_m = x;
  r.start_y_m = y;
  r.start_yaw_rad = yaw;
  r.depth_noise.enabled = false;
  r.camera.max_range_m = 20;
  return r;
}

inline RobotSpec multirotor(const std::string& name, double x, double y, double z) {
  RobotSpec r = ground_robot(name, x, y);
  r.kind = RobotKind::kMultirotor;
  r.start_z_m = z;
  r.nominal_speed_mps = 0.6;
  r.camera.baseline_m = 0.11;
  r.camera.mount_up_m = 0.0;
  return r;
}

inline std::unique_ptr<TeamSim> make_sim(const SceneSpec& scene, std::vector<RobotSpec> robots,
                                         bool rendering, uint64_t seed = 1) {
  TeamSimConfig config;
  config.rendering = rendering;
  config.seed = seed;
  auto sim = TeamSim::create(scene, std::move(robots), config);
  EXPECT_TRUE(sim) << (sim ? "" : sim.error());
  return sim ? std::move(sim).value() : nullptr;
}

}  // namespace scancrew::sim::test
