#include "components/mission_monitor/surface_coverage.hpp"

#include <cmath>

#include "sim/mesh_io.hpp"
#include "sim/scene.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::mission_monitor {

Result<SurfaceCoverage, std::string> SurfaceCoverage::from_scene(
    const std::string& scene_path, const SurfaceCoverageConfig& config,
    const std::vector<eval::TeamStart>& team) {
  auto scene = sim::load_scene(scene_path);
  if (!scene) {
    std::string all;
    for (const auto& e : scene.error()) all += (all.empty() ? "" : "; ") + e;
    return make_unexpected(all);
  }
  auto meshes = sim::load_scene_meshes(*scene);
  if (!meshes) return make_unexpected(scene_path + ": " + meshes.error());
  auto truth = sim::sample_surfaces(*scene, *meshes,
                                    {.density_per_m2 = config.density_per_m2,
                                     .seed = config.seed,
                                     .visibility_rays = config.visibility_rays});
  if (!truth) return make_unexpected(scene_path + ": " + truth.error());
  std::vector<uint8_t> observable;
  if (!team.empty()) {
    auto flags = eval::team_observable(*scene, *meshes, truth->points, truth->normals, team);
    if (!flags) return make_unexpected(scene_path + ": reachable ground truth: " + flags.error());
    observable = std::move(flags).value();
  }
  return SurfaceCoverage(std::move(truth->points), config, std::move(observable));
}

size_t SurfaceCoverage::observable_points() const {
  size_t n = 0;
  for (uint8_t o : observable_) n += o != 0 ? 1 : 0;
  return n;
}

CoverageShare SurfaceCoverage::measure_shares(const tsdf::MapSnapshot& map) const {
  CoverageShare share;
  if (points_.empty()) return share;
  // projective distances along grazing rays overestimate the distance to the surface (the
  // floor seen from 0.35 m), so the test is "observed and not clamped to ±μ", not |d| small
  const double tolerance = config_.truncation_share * map.config().truncation_m;
  const bool split = observable_.size() == points_.size();
  size_t seen = 0, observable = 0, seen_observable = 0;
  for (size_t i = 0; i < points_.size(); ++i) {
    const auto& p = points_[i];
    const tsdf::Voxel* v =
        map.voxel(tsdf::voxel_of(Eigen::Vector3d(p[0], p[1], p[2]), map.voxel_m()));
    const bool hit =
        v != nullptr && v->weight > config_.min_weight && std::abs(v->distance_m) < tolerance;
    seen += hit ? 1 : 0;
    if (split && observable_[i] != 0) {
      ++observable;
      seen_observable += hit ? 1 : 0;
    }
  }
  share.all = static_cast<double>(seen) / static_cast<double>(points_.size());
  if (split && observable > 0)
    share.reachable = static_cast<double>(seen_observable) / static_cast<double>(observable);
  return share;
}

}  // namespace scancrew::mission_monitor
