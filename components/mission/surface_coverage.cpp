#include "components/mission/surface_coverage.hpp"

#include <cmath>

#include "sim/mesh_io.hpp"
#include "sim/scene.hpp"
#include "sim/surface_sampler.hpp"

namespace scancrew::mission {

Result<SurfaceCoverage, std::string> SurfaceCoverage::from_scene(
    const std::string& scene_path, const SurfaceCoverageConfig& config) {
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
  return SurfaceCoverage(std::move(truth->points), config);
}

double SurfaceCoverage::measure(const tsdf::MapSnapshot& map) const {
  if (points_.empty()) return 0;
  // projective distances along grazing rays overestimate the distance to the surface (the
  // floor seen from 0.35 m), so the test is "observed and not clamped to ±μ", not |d| small
  const double tolerance = config_.truncation_share * map.config().truncation_m;
  size_t seen = 0;
  for (const auto& p : points_) {
    const tsdf::Voxel* v =
        map.voxel(tsdf::voxel_of(Eigen::Vector3d(p[0], p[1], p[2]), map.voxel_m()));
    if (v != nullptr && v->weight > config_.min_weight && std::abs(v->distance_m) < tolerance)
      ++seen;
  }
  return static_cast<double>(seen) / static_cast<double>(points_.size());
}

}  // namespace scancrew::mission
