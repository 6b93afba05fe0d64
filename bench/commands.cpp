#include "bench/commands.hpp"

#include <memory>
#include <string>

#include "bench/dds/dds_bench.hpp"
#include "bench/ipc/ipc_bench.hpp"
#include "bench/ise/ise_bench.hpp"
#include "bench/perception/perception_bench.hpp"
#include "bench/pipeline/pipeline_bench.hpp"
#include "bench/planner/planner_bench.hpp"
#include "bench/sim/sim_bench.hpp"
#include "bench/tsdf/tsdf_bench.hpp"
#include "bench/tsp/tsp_bench.hpp"

namespace scancrew::bench {

namespace {

using cli::CommandTable;

void add_ipc(CLI::App& bench, CommandTable& table) {
  auto [ipc, o] = table.add_with_options<IpcOptions>(
      bench, "ipc", "publish -> callback latency: scancrew vs Fast DDS and iceoryx", run_ipc_bench);
  ipc->add_flag("--json", o->json, "print one JSON object");
  ipc->add_option("--samples", o->samples, "messages per case")->check(CLI::Range(10, 1000000));
  ipc->add_option("--spin-us", o->spin_us, "scancrew receiver: spin before blocking, us")
      ->check(CLI::Range(0, 100000));
  ipc->add_option_function<std::string>(
         "--fastdds-intraprocess",
         [o = o](const std::string& v) { o->fastdds_intraprocess = v == "full"; },
         "Fast DDS intra-process delivery: full (library default) or off (data-sharing path)")
      ->check(CLI::IsMember({"full", "off"}));
}

void add_sim(CLI::App& bench, CommandTable& table) {
  auto [sim, o] = table.add_with_options<SimBenchOptions>(
      bench, "sim", "simulator: render time per stereo pair, real-time factor", run_sim_bench);
  sim->add_flag("--json", o->json, "print one JSON object");
  sim->add_option("--scene", o->scene_path, "scene file")->check(CLI::ExistingFile);
  sim->add_option("--renders", o->renders, "stereo pairs timed per size")
      ->check(CLI::Range(5, 100000));
  sim->add_option("--sim-seconds", o->sim_seconds, "simulated seconds per case")
      ->check(CLI::Range(0.1, 3600.0));
}

void add_perception(CLI::App& bench, CommandTable& table) {
  auto [perception, o] = table.add_with_options<PerceptionBenchOptions>(
      bench, "perception",
      "stereo depth and VIO on a recorded parking-lot sequence: time and error",
      run_perception_bench);
  perception->add_flag("--json", o->json, "print one JSON object");
  perception->add_option("--scene", o->scene_path, "scene to record in")->check(CLI::ExistingFile);
  perception
      ->add_option("--recording", o->recording,
                   "play this .mcap (stereo, imu, pose_gt, depth_gt) instead of recording one")
      ->check(CLI::ExistingFile);
  perception->add_option("--robot", o->robot,
                         "play only this robot namespace's topics of a mission recording");
  perception->add_flag("--no-coast", o->no_coast,
                       "VIO with max_coast_s 0: each failed frame a loss (as before coasting)");
  perception->add_flag("--vio-only", o->vio_only, "the odometry only, no stereo depth");
  perception->add_option("--keep", o->keep, "write the recording made to this path and keep it");
  perception->add_option("--distance", o->distance_m, "metres to drive (default 62)")
      ->check(CLI::Range(0.5, 10000.0));
  perception->add_option("--rpe-segment", o->rpe_segment_m, "RPE segment length, m (default 10)")
      ->check(CLI::Range(0.1, 10000.0));
  perception->add_option("--width", o->width, "image width (default 320)")
      ->check(CLI::Range(64u, 1920u));
  perception->add_option("--height", o->height, "image height (default 256)")
      ->check(CLI::Range(64u, 1080u));
  perception->add_option("--seed", o->seed, "simulator seed (default 1)");
}

void add_tsdf(CLI::App& bench, CommandTable& table) {
  auto [tsdf, o] = table.add_with_options<TsdfBenchOptions>(
      bench, "tsdf", "TSDF integration and meshing: time, memory, accuracy; scancrew vs Open3D",
      run_tsdf_bench);
  tsdf->add_flag("--json", o->json, "print one JSON object");
  tsdf->add_option("--scene", o->scene_path, "scene to render in")->check(CLI::ExistingFile);
  tsdf->add_option("--frames", o->frames,
                   "depth frames per resolution (default 60; 10 with --quick)")
      ->check(CLI::Range(1, 100000));
  tsdf->add_flag("--quick", o->quick,
                 "320x256, voxel 0.2 m, range 5 m, 10 frames only (smoke test)");
  tsdf->add_option("--repeat", o->repeats,
                   "runs per system and configuration; the fastest is reported (default 5)")
      ->check(CLI::Range(1, 100));
  tsdf->add_option("--density", o->density_per_m2, "ground-truth points per m2 (default 2000)")
      ->check(CLI::Range(1.0, 100000.0));
  tsdf->add_option("--seed", o->seed, "depth noise and ground-truth seed (default 1)");
  tsdf->add_option("--weight", o->weight,
                   "scancrew's measurement weight (default: the TsdfConfig's, inverse_square)")
      ->check(CLI::IsMember({"inverse_square", "constant"}));
  tsdf->add_option("--w-th", o->w_th, "scancrew's known-voxel weight W_th (default 0.3)")
      ->check(CLI::Range(1e-6, 1000.0));
  tsdf->add_option("--mesh-min-weight", o->mesh_min_weight,
                   "weight from which the mesher counts a voxel observed (default: MesherConfig's)")
      ->check(CLI::Range(1e-9, 1000.0));
  tsdf->add_option("--sizes", o->sizes, "image sizes, e.g. 640x480 (default both)")->delimiter(',');
  tsdf->add_option("--voxels", o->voxels_m, "voxel sizes in m (default 0.1,0.2,0.3)")
      ->delimiter(',')
      ->check(CLI::Range(0.01, 2.0));
  tsdf->add_option("--ranges", o->ranges_m, "depth ranges in m (default 5,8)")
      ->delimiter(',')
      ->check(CLI::Range(0.5, 50.0));
}

void add_ise(CLI::App& bench, CommandTable& table) {
  auto [ise, o] = table.add_with_options<IseBenchOptions>(
      bench, "ise",
      "ISE extraction, viewpoints, clusters and gain: incremental and full update time",
      run_ise_bench);
  ise->add_flag("--json", o->json, "print one JSON object");
  ise->add_option("--frames", o->frames,
                  "depth frames per scene (default 300 parking lot, 1000 powerplant)")
      ->check(CLI::Range(1, 100000));
  ise->add_flag("--quick", o->quick,
                "80 parking-lot frames, a tenth of the powerplant lap, one full() (smoke test)");
  ise->add_option("--repeat", o->repeats,
                  "full() calls per scene; the fastest is reported (default 3)")
      ->check(CLI::Range(1, 100));
  ise->add_option("--warmup", o->warmup,
                  "first updates left out of the incremental figures (default 3)")
      ->check(CLI::Range(0, 1000));
  ise->add_option("--seed", o->seed, "depth noise seed (default 1)");
  ise->add_option("--scenes", o->scenes, "parking_lot, powerplant (default both)")
      ->delimiter(',')
      ->check(CLI::IsMember({"parking_lot", "powerplant"}));
}

void add_tsp(CLI::App& bench, CommandTable& table) {
  auto [tsp, o] = table.add_with_options<TspBenchOptions>(
      bench, "tsp",
      "(max)ATSP solver: TSPLIB gap and time per instance, maxATSP time on 50-200 clusters",
      run_tsp_bench);
  tsp->add_flag("--json", o->json, "print one JSON object");
  tsp->add_option("--dir", o->dir, "folder of the TSPLIB .atsp files (default data/tsplib_atsp)")
      ->check(CLI::ExistingDirectory);
  tsp->add_flag("--quick", o->quick,
                "br17, ftv33, ftv38 and two maxATSP instances per size (smoke test)");
  tsp->add_option("--seed", o->seed, "solver seed (default 1)");
  tsp->add_option("--kicks-per-node", o->kicks_per_node,
                  "TSPLIB iteration budget: kicks per node (default 500)")
      ->check(CLI::Range(1, 1000000));
  tsp->add_option("--repeat", o->repeats, "maxATSP instances per size (default 5)")
      ->check(CLI::Range(1, 1000));
}

void add_planner(CLI::App& bench, CommandTable& table) {
  auto [planner, o] = table.add_with_options<PlannerBenchOptions>(
      bench, "planner", "low-level planner (LazyPRM*): query time, first query and reused roadmap",
      run_planner_bench);
  planner->add_flag("--json", o->json, "print one JSON object");
  planner
      ->add_option("--frames", o->frames,
                   "frames per scene (default 300 parking lot, 1000 powerplant)")
      ->check(CLI::Range(1, 100000));
  planner->add_option("--queries", o->queries, "reused-roadmap queries per scene (100)")
      ->check(CLI::Range(1, 100000));
  planner->add_option("--firsts", o->firsts, "first queries, fresh planners (10)")
      ->check(CLI::Range(1, 10000));
  planner->add_flag("--quick", o->quick, "80 + 100 frames, 20 + 3 queries per scene (smoke test)");
  planner->add_option("--seed", o->seed, "depth noise, queries, OMPL (default 1)");
  planner->add_option("--scenes", o->scenes, "parking_lot, powerplant (default both)")
      ->delimiter(',')
      ->check(CLI::IsMember({"parking_lot", "powerplant"}));
}

void add_dds(CLI::App& bench, CommandTable& table) {
  auto [dds, o] = table.add_with_options<DdsBenchOptions>(
      bench, "dds",
      "team network: latency and throughput with and without DDS-Security, the bridge and "
      "Fast DDS side by side",
      run_dds_bench);
  dds->add_flag("--json", o->json, "print one JSON object");
  dds->add_option("--samples", o->samples, "latency messages per case (1000)")
      ->check(CLI::Range(10, 1000000));
  dds->add_flag("--quick", o->quick,
                "64 B and 64 KiB, 100 messages per case, a burst of 100 (smoke test)");
  dds->add_option("--window", o->window,
                  "throughput: messages unreceived at most (default: the depth, 50)")
      ->check(CLI::Range(1, 50));
  dds->add_option("--bridge-poll-s", o->bridge_poll_period_s,
                  "the bridges' import poll period, s (their default: 0.002)")
      ->check(CLI::Range(1e-4, 1.0));
}

void add_pipeline(CLI::App& bench, CommandTable& table) {
  auto [pipeline, o] = table.add_with_options<PipelineBenchOptions>(
      bench, "pipeline",
      "one robot's graph on the wall clock: latency per stage and end to end, highest camera "
      "rate without dropped frames",
      run_pipeline_bench);
  pipeline->add_flag("--json", o->json, "print one JSON object");
  pipeline->add_flag("--quick", o->quick,
                     "12 pairs per trial, 2 search trials per size (smoke test)");
  pipeline->add_option("--launch", o->launch_path, "the graph (launch file)")
      ->check(CLI::ExistingFile);
  pipeline->add_option("--scene", o->scene_path, "scene to render the pairs in")
      ->check(CLI::ExistingFile);
  pipeline->add_option("--sizes", o->sizes, "image sizes (default 320x256,640x480)")
      ->delimiter(',');
  pipeline->add_option("--frames", o->frames, "stereo pairs per trial (100)")
      ->check(CLI::Range(2, 100000));
  pipeline->add_option("--rate", o->nominal_rate_hz, "nominal camera rate, Hz (5)")
      ->check(CLI::Range(0.1, 1000.0));
  pipeline->add_option("--threads", o->threads, "executor threads (2)")->check(CLI::Range(1, 64));
  pipeline->add_option("--trials", o->max_trials, "rate-search trials per size (8)")
      ->check(CLI::Range(1, 100));
  pipeline->add_option("--set", o->sets,
                       "override a launch parameter: name.key=value (as scancrew run --set)");
  pipeline->add_option("--seed", o->seed, "simulator seed (default 1)");
  pipeline
      ->add_option("--run", o->run_dir,
                   "a mission's run directory: print its camera-to-command latency "
                   "(metrics.json) instead of running the bench")
      ->check(CLI::ExistingDirectory);
}

}  // namespace

void add_bench_commands(CLI::App& bench, CommandTable& table) {
  add_ipc(bench, table);
  add_sim(bench, table);
  add_perception(bench, table);
  add_tsdf(bench, table);
  add_ise(bench, table);
  add_tsp(bench, table);
  add_planner(bench, table);
  add_dds(bench, table);
  add_pipeline(bench, table);
}

}  // namespace scancrew::bench
