#pragma once

// `scancrew eval --mesh M.ply --scene S.yaml`: scores a reconstructed mesh against the
// scene's ground truth (thesis 2.6.2, 5.4; eval/reconstruction_error.hpp): coverage within
// e_max = r_v·√3/2 and the signed error along the ground-truth normals. The ground truth is
// sampled as `scancrew groundtruth` samples it (same density and seed give the same points).

#include <cstdint>
#include <string>

namespace scancrew::cli {

struct EvalOptions {
  std::string mesh_path;          // PLY (core/io/ply.hpp)
  std::string scene_path;         // scene YAML
  double voxel_size_m = 0.2;      // r_v of the reconstruction; sets e_max
  double density_per_m2 = 10000;  // ground-truth points per m² (the thesis's density)
  uint64_t seed = 1;
  int visibility_rays = 64;  // the mesh visibility test (sim/surface_sampler.hpp); 0: off
  std::string missed_path;   // "": none; else the points not covered, as a PLY with normals
  bool json = false;         // one JSON object on stdout instead of the summary
};

// 0 on success (also when nothing is covered: that is a result), 2 on bad input.
int run_eval(const EvalOptions& options);

}  // namespace scancrew::cli
