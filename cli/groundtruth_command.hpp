#pragma once

// `scancrew groundtruth <scene.yaml> --out FILE.ply`: the ground truth a reconstruction is
// scored against — points with normals on the scene's visible surfaces at a fixed density
// (sim/surface_sampler.hpp), written as a binary PLY.

#include <cstdint>
#include <string>

namespace scancrew::cli {

struct GroundTruthOptions {
  std::string scene_path;
  std::string out_path;
  double density_per_m2 = 10000;  // the thesis's density
  uint64_t seed = 1;
  int visibility_rays = 64;  // the mesh visibility test (sim/surface_sampler.hpp); 0: off
};

int run_groundtruth(const GroundTruthOptions& options);

}  // namespace scancrew::cli
