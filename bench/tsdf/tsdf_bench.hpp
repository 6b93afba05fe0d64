#pragma once

// `scancrew bench tsdf`: TSDF integration and meshing, scancrew's tsdf component side by
// side with Open3D's ScalableTSDFVolume (figures: docs/mapping_bench.md).
//
//   1. frames: a ground robot's noisy depth along a loop around the parking lot's pillars
//      (depth_sequence.hpp), rendered once per resolution (320 × 256, 640 × 480; 90°
//      horizontal FOV) and reused by every configuration and both systems
//   2. for each voxel size (0.1, 0.2, 0.3 m) and range (5, 8 m), truncation 3 voxels:
//      integrate every frame (each call timed), mesh once (timed), memory per m² of mesh
//   3. accuracy: coverage and RMSE of each mesh against ground-truth points of the whole
//      scene (sim/surface_sampler.hpp), e_max = voxel·√3/2 (eval/reconstruction_error.hpp)
//
// Prints {"results": [{"system", "width", "height", "voxel_m", "range_m", "ms_per_frame",
// "coverage", "rmse_m", ...}], "comparisons": [...], ...} with --json, else a table.
// --quick: 320 × 256, voxel 0.2 m, range 5 m, 10 frames (a smoke test).

#include <cstdint>
#include <string>
#include <vector>

namespace scancrew::bench {

struct TsdfBenchOptions {
  std::string scene_path = "launch_cfg/scenes/parking_lot.yaml";
  int frames = 0;  // per resolution; 0: 60, or 10 with quick
  bool quick = false;
  // each system integrates the sequence this many times per configuration; the fastest
  // run's frame times are reported (all runs' means are listed)
  int repeats = 5;
  double density_per_m2 = 2000;  // ground-truth points
  uint64_t seed = 1;             // depth noise and ground-truth sampling
  // scancrew's TsdfConfig::weight and w_th; empty / 0 keep the defaults (inverse_square, 0.3)
  std::string weight;
  double w_th = 0;
  // the mesher's min_weight; 0 keeps the MesherConfig default
  double mesh_min_weight = 0;
  // configurations to run; empty: all (or the quick one)
  std::vector<std::string> sizes;  // "WxH"
  std::vector<double> voxels_m;
  std::vector<double> ranges_m;
  bool json = false;
};

int run_tsdf_bench(const TsdfBenchOptions& options);

}  // namespace scancrew::bench
