#include "eval/team_reachable.hpp"

#include "eval/free_space.hpp"
#include "eval/reachable_truth.hpp"
#include "sim/scene_solids.hpp"

namespace scancrew::eval {

Result<std::vector<uint8_t>, std::string> team_observable(
    const sim::SceneSpec& scene, const std::vector<io::TriangleMesh>& placed_meshes,
    const std::vector<std::array<float, 3>>& points,
    const std::vector<std::array<float, 3>>& normals, const std::vector<TeamStart>& team) {
  std::vector<uint8_t> observable(points.size(), 0);
  if (team.empty()) return observable;
  const sim::SceneSolids solids(scene, placed_meshes);
  for (const robot::RobotKind kind : {robot::RobotKind::kGround, robot::RobotKind::kMultirotor}) {
    std::vector<msg::Vec3> starts;
    for (const TeamStart& t : team)
      if (t.kind == kind) starts.push_back(t.position);
    if (starts.empty()) continue;
    auto free_space = FreeSpace::build(solids, scene, default_body(kind), starts);
    if (!free_space) return make_unexpected(free_space.error());
    for (size_t i = 0; i < starts.size(); ++i)
      if (!free_space->start_free(i))
        return make_unexpected(scene.source + ": a " + robot::to_string(kind) +
                               " robot's body at (" + std::to_string(starts[i].x) + ", " +
                               std::to_string(starts[i].y) + ", " + std::to_string(starts[i].z) +
                               ") overlaps the scene: its reachable space is empty");
    auto seen = reachable_truth(points, normals, solids, *free_space,
                                observer_from_camera(sim::default_camera(kind)));
    if (!seen) return make_unexpected(seen.error());
    for (size_t i = 0; i < points.size(); ++i) observable[i] |= seen->observable[i];
  }
  return observable;
}

double share_of_observable(const std::vector<uint8_t>& observable,
                           const std::vector<uint8_t>& covered) {
  size_t n = 0, hit = 0;
  for (size_t i = 0; i < observable.size() && i < covered.size(); ++i) {
    if (observable[i] == 0) continue;
    ++n;
    hit += covered[i] != 0 ? 1 : 0;
  }
  return n == 0 ? -1.0 : static_cast<double>(hit) / static_cast<double>(n);
}

}  // namespace scancrew::eval
