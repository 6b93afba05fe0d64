#pragma once

// SurfaceCoverage: how much of the scene's true surface a map has observed, while the
// mission runs (the "coverage over time" of the run report). The final figure of a mission
// is the evaluation of its mesh (eval/reconstruction_error.hpp, thesis 2.6.2); this online
// estimate needs no mesh: a ground-truth surface point p counts as seen when the map's
// voxel at p has been observed (weight > min_weight, as the mesher's min_weight: 0 meshes
// every observed voxel) with |d| < truncation_share · μ — a distance not clamped to the
// truncation, so a surface was measured within μ of p (the mesher then puts a zero crossing
// there). Not |d| < a voxel: projective distances along grazing rays (the floor seen from
// 0.35 m) overestimate the distance to the surface several times. Ground truth:
// sim::sample_surfaces at a low density (the points are a uniform sample of the visible surface, so
// the share is an unbiased estimate of the surface fraction seen).

#include <array>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "core/tsdf/tsdf_map.hpp"
#include "eval/team_reachable.hpp"

namespace scancrew::mission_monitor {

struct SurfaceCoverageConfig {
  double density_per_m2 = 50;      // ground-truth points per m² of visible surface
  double truncation_share = 0.99;  // |d| < truncation_share · μ counts as seen
  double min_weight = 0;           // a voxel counts once its weight is above this
  uint64_t seed = 1;
  int visibility_rays = 64;  // the ground truth's mesh visibility test (surface_sampler.hpp)
};

// What a map has seen: of every ground-truth point, and of those the team can observe
// (reachable < 0: no team given, not measured).
struct CoverageShare {
  double all = 0;
  double reachable = -1;
};

class SurfaceCoverage {
 public:
  // Loads the scene (YAML) and samples its surface; with a team, also marks the points its
  // robots can observe (eval/team_reachable.hpp). Errors name the scene and the cause.
  static Result<SurfaceCoverage, std::string> from_scene(
      const std::string& scene_path, const SurfaceCoverageConfig& config,
      const std::vector<eval::TeamStart>& team = {});
  SurfaceCoverage(std::vector<std::array<float, 3>> points, SurfaceCoverageConfig config,
                  std::vector<uint8_t> observable = {})
      : points_(std::move(points)), observable_(std::move(observable)), config_(config) {}

  // The share of the ground-truth points the map has seen, in [0, 1] (0 without points).
  double measure(const tsdf::MapSnapshot& map) const { return measure_shares(map).all; }
  CoverageShare measure_shares(const tsdf::MapSnapshot& map) const;
  size_t points() const { return points_.size(); }
  size_t observable_points() const;

 private:
  std::vector<std::array<float, 3>> points_;
  std::vector<uint8_t> observable_;  // empty: not known
  SurfaceCoverageConfig config_;
};

}  // namespace scancrew::mission_monitor
