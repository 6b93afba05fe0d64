#pragma once

// MeshScore: a mission's meshes scored against the scene's ground truth, one per mapper of
// the run (or, in a process of a team split over processes, each mesh_<ns>.ply the others
// wrote into the run directory): coverage and error at the e_max of the map's voxel size,
// and the share of the surface the team can observe (docs/evaluation.md).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "components/mission_monitor/mission_monitor.hpp"
#include "eval/reconstruction_error.hpp"
#include "executors/launch.hpp"

namespace scancrew::cli {

struct MeshScore {
  std::string robot_ns;  // whose map: a robot's namespace, or "station" (a centralized mapper)
  std::string from;      // robot_ns, or "robot_ns/component" where one place has two mappers
  std::string mesh_path, octomap_path;
  double voxel_m = 0;
  double e_max_m = 0;  // the evaluation's
  std::optional<eval::ReconstructionError> error;
  double coverage_reachable = NAN;  // of the points the team can observe
};

// Each mapper's mesh (written as the launch stopped) against the scene's ground truth; the
// meshes written into the run directory since `started` when the launch has no mapper.
std::vector<MeshScore> score_meshes(const Launch& launch,
                                    const mission_monitor::MissionMonitor& monitor,
                                    std::filesystem::file_time_type started);

// Whether s stands for its place: a place with two mappers (a planning map and a finer
// reconstruction map) is represented by its finer one, so that the choice does not hang on
// comparing coverages scored at two e_max.
bool represents_place(const std::vector<MeshScore>& scores, const MeshScore& s);

// The mesh the run is judged by: the best-covering scored mesh among those that represent
// their place, else the first such mesh at all; nullptr when there is none.
const MeshScore* best_mesh(const std::vector<MeshScore>& scores);

}  // namespace scancrew::cli
