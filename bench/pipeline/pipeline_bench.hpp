#pragma once

// `scancrew bench pipeline`: latency through one ground robot's graph and the highest
// camera rate it sustains without dropping frames, at 320 × 256 and 640 × 480 (figures:
// docs/pipeline_bench.md). The graph is launch_cfg/bench/pipeline.yaml: stereo pair →
// stereo_depth (SGBM) → tsdf_mapper → ise_extractor → high_level_planner (TSGA, N = 1),
// with the parameters of the single-robot parking-lot mission, on the wall clock and a
// multi-threaded executor (threads: the machine's cores, 2 by default), as on the robot.
//
//   1. capture: the team simulator renders `frames` stereo pairs and ground-truth poses of a
//      ground robot driving along the parking lot's pillars at 0.5 m/s, a pair every
//      1 / nominal_rate_hz of sim time (lockstep; kept in memory: bench_frame_capture);
//   2. trials: a fresh launch of the graph (empty map) per trial, after one unreported
//      warm-up trial of 5 pairs per size (one-off costs of the process's first matches and
//      integrations, which a running robot has paid long ago); a thread of the bench
//      publishes the pairs on /r1/pose_gt and /r1/stereo at the trial's camera rate on the
//      wall clock, as a camera driver would (it never waits for the graph), then waits for
//      the graph to drain. Per trial:
//        - dropped frames: pairs that never reached the map (published − integrated by
//          tsdf_mapper, plus pairs the camera found no free slot for);
//        - per stage, the compute time of each callback that did the stage's work (the
//          runtime's Tracer) and the latency from its input's publication and from the
//          pair's publication to its output's publication (the capture stamp every stage
//          keeps chains them: bench_pipeline_probe); end to end = pair published → the
//          plan that follows it. The mapper publishes a snapshot every snapshot_every
//          images; the ISE extractor runs on the newest snapshot when free (depth-1 queue),
//          the planner on each cluster set: their latencies are per snapshot, ISE run and
//          plan, not per pair;
//   3. the highest sustained rate, measured: the trial at nominal_rate_hz, then doubling
//      while no frame drops, then bisection between the highest passing and the lowest
//      failing rate until they are within `tolerance`, at most max_trials trials.
//
// Prints one JSON object with --json ({"sizes": [{"width", "height", "nominal": {trial},
// "max_rate_hz", "first_failing_rate_hz", "at_max_rate": {trial}, "trials": [...]}], ...}),
// else tables. --quick: 12 pairs per trial, 2 search trials (a smoke test).
// --run DIR: no bench; the camera-to-command latency a mission run measured (run_latency.hpp).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace scancrew::bench {

struct PipelineBenchOptions {
  std::string launch_path = "launch_cfg/bench/pipeline.yaml";
  std::string scene_path = "launch_cfg/scenes/parking_lot.yaml";
  std::vector<std::string> sizes;  // "WxH"; empty: 320x256 and 640x480
  uint32_t frames = 0;             // pairs per trial; 0: 100 (quick: 12)
  double nominal_rate_hz = 5.0;    // the missions' camera rate (thesis table 5.3)
  size_t threads = 2;              // executor threads (the robot computer's cores)
  double tolerance = 0.1;          // bisection stops when failing / passing ≤ 1 + tolerance
  int max_trials = 0;              // search trials after the nominal one; 0: 8 (quick: 2)
  std::vector<std::string> sets;   // launch overrides, as `scancrew run --set`
  uint64_t seed = 1;               // simulator seed
  bool quick = false;
  bool json = false;
  // a mission's run directory: print its camera-to-command latency (run_latency.hpp)
  // instead of running the bench
  std::string run_dir;
};

int run_pipeline_bench(const PipelineBenchOptions& options);

}  // namespace scancrew::bench
