#pragma once

// `scancrew bench ise`: ISE extraction, viewpoints, visibility, clustering and gain
// (core/ise, thesis 2.4.2, 2.4.3), incremental and full, on two maps built while
// the bench runs (figures: docs/ise_bench.md).
//
//   parking lot, voxel 0.2 m: a ground robot's noisy depth along the loop around the
//     pillars (bench/tsdf/depth_sequence.hpp: 320 × 256, range [0.3, 5] m, here a frame
//     every 0.4 s, 0.2 m); ground-robot viewpoints with the parameters of table 5.3
//     (δ_pose 1.3 m, d_v 2 m, d_v^max 3.5 m, 0.55 m footprint, camera 0.35 m above the floor)
//   powerplant, voxel 0.3 m: a multirotor's lap around the plant at 2 to 12 m
//     (flight_sequence.hpp: 752 × 434, range [1.6, 8] m, a frame every 0.25 m);
//     multirotor viewpoints with the parameters of table 2.1 (δ_pose 4.7 m, d_v 2 m,
//     d_v^max 5 m, 1 m collision radius)
//
// Each frame is integrated into the TSDF map (tsdf::Integrator, W_th 0.3, 1/z² weights)
// and IsePipeline::update() is timed on the map's snapshot: incremental_ms is the mean
// over the updates after the first `warmup`; full_ms is a fresh pipeline's full() on the
// last snapshot, fastest of `repeats`. The two are checked to agree (matches_full), and the
// visibility stage's cost per viewpoint is probed from the run's camera poses.
//
// Prints {"results": [{"scene", "voxel_m", "ises", "clusters", "incremental_ms",
// "full_ms", ...}], "targets": [...], ...} with --json, else a table. Targets (2 cores):
// incremental ≤ 50 ms, full ≤ 500 ms. --quick: 80 parking-lot frames, the first tenth of
// the lap in 100 smaller frames, one full() (a smoke test of a few seconds).

#include <cstdint>
#include <string>
#include <vector>

namespace scancrew::bench {

struct IseBenchOptions {
  std::string parking_lot_path = "launch_cfg/scenes/parking_lot.yaml";
  std::string powerplant_path = "launch_cfg/scenes/powerplant.yaml";
  int frames = 0;  // per scene; 0: 300 parking lot, 1000 powerplant (quick: 80, 100)
  bool quick = false;
  int repeats = 3;  // full() calls per scene; the fastest is reported
  int warmup = 3;   // updates left out of the incremental figures
  uint64_t seed = 1;
  std::vector<std::string> scenes;  // "parking_lot", "powerplant"; empty: both
  bool json = false;
};

int run_ise_bench(const IseBenchOptions& options);

}  // namespace scancrew::bench
