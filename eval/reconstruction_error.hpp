#pragma once

// Reconstruction error: a reconstructed triangle mesh scored against ground-truth points
// with normals on the scene's visible surfaces (sim/surface_sampler.hpp), as in the thesis
// (2.6.2, 5.4).
//
//   e_max = r_v·√3/2, half the diagonal of a voxel of size r_v: the largest error of a
//           surface that falls anywhere in the right voxel.
//   For each ground-truth point p with unit normal n, q is the point of the mesh nearest p
//   (exact point-to-triangle distance). p is covered when |q − p| <= e_max.
//   Signed error of a covered point: (q − p)·n, measured along the ground truth's normal as
//   M3C2 does (Lague et al., ISPRS J. 2013): positive when the reconstruction lies outside
//   the surface (on the free-space side), negative when it lies inside.
//   Coverage = covered / points; mean, standard deviation (population) and RMSE of the signed
//   error over the covered points (RMSE² = mean² + std²).
//
// Plain function on plain data; parallel over the points (TBB) and deterministic: the same
// inputs give the same figures bit for bit whatever the number of threads.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/io/triangle_mesh.hpp"
#include "core/result.hpp"

namespace scancrew::eval {

// e_max for a voxel size r_v: r_v·√3/2.
double max_error_for_voxel(double voxel_size_m);

struct ReconstructionErrorConfig {
  double e_max_m = 0;            // > 0: max_error_for_voxel(r_v)
  bool per_point_error = false;  // fill ReconstructionError::point_error_m
};

// Why the error figures may be undefined. With no covered point they are NaN, not 0 (a 0
// would read as a perfect reconstruction).
enum class EvalStatus : uint8_t {
  kOk,              // at least one point covered
  kEmptyMesh,       // the mesh has no triangles: coverage 0
  kNothingCovered,  // no point within e_max of the mesh: coverage 0
};
std::string_view to_string(EvalStatus status);

struct ReconstructionError {
  EvalStatus status = EvalStatus::kOk;
  size_t gt_points = 0;
  size_t covered = 0;
  double coverage = 0;      // covered / gt_points, in [0, 1]
  double mean_error_m = 0;  // signed error over the covered points
  double std_error_m = 0;
  double rmse_m = 0;
  double e_max_m = 0;  // the e_max used
  size_t mesh_triangles = 0;
  // with per_point_error: the signed error of each point in input order, NaN when not covered
  std::vector<float> point_error_m;
};

// The input checks of reconstruction_error() but the one for no points (profile_misses()
// takes an empty set): e_max, counts, finite points and non-zero normals, the mesh.
Result<void, std::string> check_eval_inputs(const io::TriangleMesh& mesh,
                                            std::span<const std::array<float, 3>> points,
                                            std::span<const std::array<float, 3>> normals,
                                            double e_max_m);

// points: world frame, m; normals: one per point, outward (they are normalised here). Fails,
// naming the culprit, on: e_max not positive and finite, no points, points and normals of
// different counts, a point or normal not finite or a zero normal, a mesh vertex not finite,
// a triangle index out of range. An empty mesh is not an error: it covers nothing
// (status kEmptyMesh).
Result<ReconstructionError, std::string> reconstruction_error(
    const io::TriangleMesh& mesh, std::span<const std::array<float, 3>> points,
    std::span<const std::array<float, 3>> normals, const ReconstructionErrorConfig& config);

}  // namespace scancrew::eval
