#pragma once

// The reachable ground truth of a team (coverage_reachable in metrics.json, the mission
// monitor's coverage over time): a point counts when a robot of some kind in the team can
// observe it from a pose reachable from that kind's starts (reachable_truth.hpp), with the
// kind's default body (free_space.hpp) and camera (sim::default_camera). A team of two kinds
// takes the union.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "interfaces/geometry.hpp"
#include "sim/mesh_io.hpp"
#include "sim/robot_model.hpp"
#include "sim/scene.hpp"

namespace scancrew::eval {

struct TeamStart {
  robot::RobotKind kind = robot::RobotKind::kGround;
  msg::Vec3 position;  // the body's (ground: on the floor)
};

// One flag per point (1: observable). Errors: a start whose body does not fit where it stands
// (the free space would hold nothing reachable), and reachable_truth's.
Result<std::vector<uint8_t>, std::string> team_observable(
    const sim::SceneSpec& scene, const std::vector<io::TriangleMesh>& placed_meshes,
    const std::vector<std::array<float, 3>>& points,
    const std::vector<std::array<float, 3>>& normals, const std::vector<TeamStart>& team);

// The share of the flagged points that `covered` marks (covered[i] != 0); -1 with none
// flagged.
double share_of_observable(const std::vector<uint8_t>& observable,
                           const std::vector<uint8_t>& covered);

}  // namespace scancrew::eval
