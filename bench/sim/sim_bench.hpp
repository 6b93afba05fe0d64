#pragma once

// `scancrew bench sim`: rendering time per stereo pair, and the real-time factor of the
// team simulator with 1, 3 and 5 robots and cameras at 5 Hz. Figures: docs/sim.md.

#include <string>

namespace scancrew::bench {

struct SimBenchOptions {
  std::string scene_path = "launch_cfg/scenes/parking_lot.yaml";
  int renders = 60;         // stereo pairs timed per resolution
  double sim_seconds = 10;  // simulated time per real-time-factor case
  bool json = false;
};

int run_sim_bench(const SimBenchOptions& options);

}  // namespace scancrew::bench
