#include "cli/mesh_scores.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "components/tsdf_mapper/tsdf_mapper.hpp"
#include "core/io/ply.hpp"
#include "eval/team_reachable.hpp"
#include "executors/log.hpp"
#include "sim/mesh_io.hpp"
#include "sim/scene.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;
using mission_monitor::MissionMonitor;

// The voxel size of an OctoMap binary file (its text header's "res" line); 0 if unreadable.
double octomap_resolution(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  for (int i = 0; i < 8 && std::getline(in, line); ++i)
    if (line.rfind("res ", 0) == 0) return std::atof(line.c_str() + 4);
  return 0;
}

// The meshes other processes of the team wrote into the run directory since `since` (a
// simulator process has no mapper: its robots' processes write mesh_<ns>.ply there).
std::vector<MeshScore> meshes_in(const fs::path& dir, fs::file_time_type since) {
  std::vector<MeshScore> scores;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("mesh_", 0) != 0 || entry.path().extension() != ".ply") continue;
    if (entry.last_write_time(ec) < since) continue;
    MeshScore s;
    s.robot_ns = name.substr(5, name.size() - 9);
    s.from = s.robot_ns;
    s.mesh_path = entry.path().string();
    const fs::path map = dir / ("map_" + s.robot_ns + ".bt");
    if (fs::exists(map, ec)) {
      s.octomap_path = map.string();
      s.voxel_m = octomap_resolution(map);
    }
    if (s.voxel_m <= 0) {
      std::fprintf(stderr,
                   "scancrew run: %s: no map_%s.bt beside it to give its voxel size; "
                   "not scored\n",
                   s.mesh_path.c_str(), s.robot_ns.c_str());
      continue;
    }
    scores.push_back(std::move(s));
  }
  std::sort(scores.begin(), scores.end(),
            [](const MeshScore& a, const MeshScore& b) { return a.robot_ns < b.robot_ns; });
  return scores;
}

// The meshes of the launch's mappers, by place: a robot's namespace, or "station" for a
// centralized mapper; "place/component" where one place has two mappers.
std::vector<MeshScore> mapper_meshes(const RunSummary& summary, const MissionMonitor& monitor) {
  std::vector<MeshScore> scores;
  std::vector<std::string> component_names;
  for (const RunSummary::Map& map : summary.maps) {
    MeshScore s;
    // a centralized mapper is the ground station's; the others are a robot's
    s.robot_ns = "station";
    if (map.mode != name_of(tsdf_mapper::kMapModeNames, tsdf_mapper::MapMode::kCentralized))
      for (const auto& r : monitor.robots())
        if (r.id == map.robot_id) s.robot_ns = r.ns;
    s.mesh_path = map.mesh_path;
    s.octomap_path = map.octomap_path;
    s.voxel_m = map.voxel_m;
    component_names.push_back(map.component);
    scores.push_back(std::move(s));
  }
  // two mappers of one place (a planning map and a finer reconstruction map) go by
  // "place/component"
  std::map<std::string, int> per_place;
  for (const MeshScore& s : scores) ++per_place[s.robot_ns];
  for (size_t i = 0; i < scores.size(); ++i)
    scores[i].from = scores[i].robot_ns +
                     (per_place[scores[i].robot_ns] > 1 ? "/" + component_names[i] : std::string());
  return scores;
}

}  // namespace

std::vector<MeshScore> score_meshes(const Launch& launch, const MissionMonitor& monitor,
                                    fs::file_time_type started) {
  std::vector<MeshScore> scores = mapper_meshes(launch.summary(), monitor);
  if (scores.empty()) scores = meshes_in(launch.out_dir(), started);
  const std::string& scene_path = monitor.config().scene;
  if (scene_path.empty()) return scores;
  auto scene = sim::load_scene(scene_path);
  if (!scene) return scores;
  auto meshes = sim::load_scene_meshes(*scene);
  if (!meshes) return scores;
  const auto truth = sim::sample_surfaces(*scene, *meshes,
                                          {.density_per_m2 = monitor.config().eval_density_per_m2,
                                           .seed = 1,
                                           .visibility_rays = monitor.config().visibility_rays});
  if (!truth) {
    std::fprintf(stderr, "scancrew run: evaluation: %s\n",
                 scancrew::log::printable(truth.error()).c_str());
    return scores;
  }
  // the points the team's robot kinds can observe from their starts (docs/evaluation.md)
  auto observable =
      eval::team_observable(*scene, *meshes, truth->points, truth->normals, monitor.team_starts());
  if (!observable)
    std::fprintf(stderr, "scancrew run: evaluation: reachable ground truth: %s\n",
                 scancrew::log::printable(observable.error()).c_str());
  for (MeshScore& s : scores) {
    if (s.mesh_path.empty()) continue;
    const auto mesh = io::read_ply_mesh(s.mesh_path);
    if (!mesh) {
      std::fprintf(stderr, "scancrew run: evaluation: %s\n",
                   scancrew::log::printable(mesh.error()).c_str());
      continue;
    }
    s.e_max_m = monitor.config().eval_e_max_m > 0 ? monitor.config().eval_e_max_m
                                                  : eval::max_error_for_voxel(s.voxel_m);
    auto r = eval::reconstruction_error(*mesh, truth->points, truth->normals,
                                        {.e_max_m = s.e_max_m, .per_point_error = true});
    if (r && observable) {
      std::vector<uint8_t> covered(r->point_error_m.size());
      for (size_t i = 0; i < covered.size(); ++i)
        covered[i] = std::isnan(r->point_error_m[i]) ? 0 : 1;
      const double share = eval::share_of_observable(*observable, covered);
      s.coverage_reachable = share >= 0 ? share : NAN;
      r->point_error_m = {};  // 4 bytes a point: not kept
    }
    if (r)
      s.error = std::move(r).value();
    else
      std::fprintf(stderr, "scancrew run: evaluation of %s: %s\n", s.mesh_path.c_str(),
                   scancrew::log::printable(r.error()).c_str());
  }
  return scores;
}

bool represents_place(const std::vector<MeshScore>& scores, const MeshScore& s) {
  return std::none_of(scores.begin(), scores.end(), [&](const MeshScore& o) {
    return o.robot_ns == s.robot_ns && o.voxel_m < s.voxel_m;
  });
}

const MeshScore* best_mesh(const std::vector<MeshScore>& scores) {
  const MeshScore* best = nullptr;
  for (const MeshScore& s : scores)
    if (s.error && represents_place(scores, s) &&
        (best == nullptr || s.error->coverage > best->error->coverage))
      best = &s;
  if (best == nullptr)
    for (const MeshScore& s : scores)
      if (!s.mesh_path.empty() && represents_place(scores, s) && best == nullptr) best = &s;
  return best;
}

}  // namespace scancrew::cli
