#pragma once

// `scancrew bench planner`: query time of the low-level planner's core
// (core/motion/motion_planner.hpp: LazyPRM* + FCL octree, thesis 2.5.3) on two
// maps built while the bench runs, as bench/ise builds them (figures:
// docs/low_level_planner.md):
//
//   parking lot, voxel 0.2 m, ground robot (ellipsoid 0.55 × 0.25 m + 0.1 m margin, unknown
//     space occupied): the TSDF bench's depth sequence around the pillars (300 frames, a
//     frame every 0.4 s);
//   powerplant, voxel 0.3 m, multirotor (sphere 1 m + 0.15 m margin, unknown space free,
//     altitude 2 to 12 m, the lap's band): the ISE bench's lap around the plant (1000 frames).
//
// The planner follows the map as it is built (update_map() on every snapshot: incremental
// octree updates, timed). Queries join two poses the robot took (free in the final map,
// at least min_query_m apart), drawn with a seeded RNG:
//   first_query: a fresh planner (empty roadmap) on the final map, one query, `firsts` times;
//   reused: one planner, `queries` queries in a row on the same roadmap.
// Every path found is checked against the scene's true geometry (boxes, cylinders, walls,
// meshes; FCL) with the thesis's body, no margin, sampled every 2 cm (ground) or 5 cm.
//
// Prints {"results": [{"scene", "robot", ..., "first_query_ms": {"median", "p95", "max"},
// "reused_ms": {...}, "paths_colliding", ...}], "targets": [...]} with --json, else a
// table. Target: median ≤ 50 ms. --quick: 80 parking-lot frames, a tenth of the lap,
// 20 reused and 3 first queries per scene (a smoke test of a few seconds).

#include <cstdint>
#include <string>
#include <vector>

namespace scancrew::bench {

struct PlannerBenchOptions {
  std::string parking_lot_path = "launch_cfg/scenes/parking_lot.yaml";
  std::string powerplant_path = "launch_cfg/scenes/powerplant.yaml";
  int frames = 0;   // per scene; 0: 300 parking lot, 1000 powerplant (quick: 80, 100)
  int queries = 0;  // reused-roadmap queries per scene; 0: 100 (quick: 20)
  int firsts = 0;   // first queries (fresh planners) per scene; 0: 10 (quick: 3)
  bool quick = false;
  uint64_t seed = 1;                // depth noise, query draw, OMPL
  std::vector<std::string> scenes;  // "parking_lot", "powerplant"; empty: both
  bool json = false;
};

int run_planner_bench(const PlannerBenchOptions& options);

}  // namespace scancrew::bench
