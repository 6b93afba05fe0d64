// scancrew: the command line. Subcommands: run, sim, robot, station, sweep, components, graph,
// render, groundtruth, scenegen, eval, report, keys, bench (ipc, dds, sim, perception, tsdf, ise,
// tsp, planner, pipeline, explore).

#include <CLI/CLI.hpp>
#include <cstdio>
#include <string>

#include "cli/eval_command.hpp"
#include "cli/explore_bench.hpp"
#include "cli/groundtruth_command.hpp"
#include "cli/keys_command.hpp"
#include "cli/mission_compose.hpp"
#include "cli/render_command.hpp"
#include "cli/report.hpp"
#include "cli/run_command.hpp"
#include "cli/scenegen_command.hpp"
#include "cli/sweep_command.hpp"
#include "executors/launch.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "mission/run_report.hpp"
#ifdef SCANCREW_WITH_BENCH
#include "bench/dds/dds_bench.hpp"
#include "bench/ipc/ipc_bench.hpp"
#include "bench/ise/ise_bench.hpp"
#include "bench/perception/perception_bench.hpp"
#include "bench/pipeline/pipeline_bench.hpp"
#include "bench/planner/planner_bench.hpp"
#include "bench/sim/sim_bench.hpp"
#include "bench/tsdf/tsdf_bench.hpp"
#include "bench/tsp/tsp_bench.hpp"
#endif

namespace {

std::unique_ptr<scancrew::Launch> compose_or_report(const std::string& path) {
  const auto text = scancrew::cli::launch_file_text(path);
  if (!text) {
    std::fprintf(stderr, "scancrew: %s; nothing was started\n",
                 scancrew::log::printable(text.error()).c_str());
    return nullptr;
  }
  auto launch = scancrew::Launch::from_string(*text, path);
  if (!launch) {
    std::fprintf(stderr, "scancrew: %s: %zu error(s); nothing was started\n", path.c_str(),
                 launch.error().size());
    for (const auto& e : launch.error())
      std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
    return nullptr;
  }
  return std::move(launch).value();
}

int cmd_components() {
  const auto& registry = scancrew::ComponentRegistry::instance();
  for (const auto& type : registry.types())
    std::printf("%-24s %s\n", type.c_str(), registry.find(type)->description.c_str());
  return 0;
}

int cmd_graph(const std::string& path) {
  auto launch = compose_or_report(path);
  if (!launch) return 2;
  scancrew::cli::print_graph(stdout, *launch);
  return launch->report().errors.empty() ? 0 : 2;
}

int cmd_report(const std::string& run_dir) {
  const auto written = scancrew::mission::write_report(run_dir);
  if (!written) {
    std::fprintf(stderr, "scancrew report: %s\n",
                 scancrew::log::printable(written.error()).c_str());
    return 1;
  }
  std::printf("report: %s/report.html\n", run_dir.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"scancrew: multi-robot 3D reconstruction (runtime, simulator, planners)"};
  app.require_subcommand(1);

  // the options of a command that runs a launch file (run, and the parts of a split team)
  const auto add_launch_options = [](CLI::App* cmd, scancrew::cli::RunOptions& o,
                                     const char* out_help, const char* robots_help) {
    cmd->add_option("launch", o.launch_path, "launch file (YAML)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--out", o.out_dir, out_help);
    cmd->add_option("--set", o.sets,
                    "override a parameter: name.key=value (a component's name, or run / executor)")
        ->expected(1)
        ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    cmd->add_option("--robots", o.robot_count, robots_help)
        ->check(CLI::Range(size_t{1}, size_t{1000}));
    cmd->add_option("--trace-events", o.trace_events,
                    "missions: callbacks kept for trace.json (24 bytes each; 0: no tracing)")
        ->capture_default_str();
  };

  scancrew::cli::RunOptions run_options;
  auto* run = app.add_subcommand(
      "run", "compose a launch file and run it; a mission writes its run directory and report");
  add_launch_options(
      run, run_options, "run directory ({out} in the launch file; default runs/<launch stem>)",
      "run the first N robots of the launch file's robots: list (default: all); a mission "
      "file is composed with N robots");

  // one process of a team split over processes (docs/processes.md)
  scancrew::cli::RunOptions part_options;
  const auto add_part = [&](const char* name, const char* what) {
    auto* cmd = app.add_subcommand(name, what);
    add_launch_options(
        cmd, part_options, "run directory, the same for every process of the team ({out})",
        "the team: the first N robots of the launch file (the same in every process)");
    return cmd;
  };
  auto* sim_part = add_part(
      "sim", "the team simulator's process of a team split over processes (lockstep leader)");
  auto* robot_part = add_part("robot", "one robot's process of a team split over processes");
  robot_part->add_option("--robot", part_options.robot_id, "this process's robot id")->required();
  auto* station_part = add_part(
      "station", "the ground station's process of a centralized team split over processes");

  scancrew::cli::SweepOptions sweep_options;
  auto* sweep = app.add_subcommand(
      "sweep", "run a mission over architectures x robots x seeds; results tables (MD, CSV)");
  sweep
      ->add_option("file", sweep_options.path,
                   "sweep file (architectures: one launch file each) or a launch file")
      ->required()
      ->check(CLI::ExistingFile);
  sweep
      ->add_option("--robots", sweep_options.robots,
                   "team sizes, e.g. 1,2,3,4 (default: every robot of each launch file)")
      ->delimiter(',')
      ->check(CLI::Range(size_t{1}, size_t{1000}));
  sweep
      ->add_option("--arch", sweep_options.archs,
                   "architectures (default: every one of the sweep file)")
      ->delimiter(',')
      ->check(CLI::IsMember({"single", "centralized", "distributed"}));
  sweep->add_option("--seeds", sweep_options.seeds, "runs per team, seeds 1..N")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  sweep->add_option("--out", sweep_options.out_dir,
                    "output folder: sweep.md, sweep.csv, a run directory per run "
                    "(default runs/sweep_<file stem>)");
  sweep
      ->add_option("--set", sweep_options.sets,
                   "override a parameter in every run: name.key=value (after the seed's)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sweep
      ->add_option("--seed-keys", sweep_options.seed_keys,
                   "parameters set to the seed (default: the sweep file's seed_keys, else "
                   "sim.seed,low_level.planner_seed)")
      ->delimiter(',');

  auto* components = app.add_subcommand("components", "list the registered component types");

  std::string graph_path;
  auto* graph =
      app.add_subcommand("graph", "print the composed graph of a launch file and check it");
  graph->add_option("launch", graph_path, "launch file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);

  scancrew::cli::RenderOptions render_options;
  auto* render =
      app.add_subcommand("render", "render a scene: stereo pair, depth and a top view, as PNG");
  render->add_option("scene", render_options.scene_path, "scene file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  render->add_option("--out", render_options.out_dir, "output folder")->required();
  render
      ->add_option("--pose", render_options.pose,
                   "x,y,yaw_deg of the robot (default: a free corner)")
      ->delimiter(',')
      ->expected(3);
  render->add_option("--kind", render_options.kind, "robot kind")
      ->check(CLI::IsMember({"ground", "multirotor"}));
  render->add_option("--z", render_options.z_m, "multirotor altitude, m");
  render->add_option("--width", render_options.width, "image width")->check(CLI::Range(16u, 1920u));
  render
      ->add_option("--height", render_options.height,
                   "image height (with the width, sets the FOV aspect)")
      ->check(CLI::Range(16u, 1080u));

  scancrew::cli::GroundTruthOptions gt_options;
  auto* groundtruth = app.add_subcommand(
      "groundtruth", "sample points with normals on a scene's visible surfaces, as a PLY");
  groundtruth->add_option("scene", gt_options.scene_path, "scene file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  groundtruth->add_option("--out", gt_options.out_path, "output file (.ply)")->required();
  groundtruth->add_option("--density", gt_options.density_per_m2, "points per m2 (default 10000)");
  groundtruth->add_option("--seed", gt_options.seed, "random seed (default 1)");
  groundtruth
      ->add_option("--visibility-rays", gt_options.visibility_rays,
                   "ray directions per point of the mesh visibility test, 0: off (default 64)")
      ->check(CLI::Range(0, 100000));

  scancrew::cli::ScenegenOptions scenegen_options;
  auto* scenegen = app.add_subcommand(
      "scenegen", "write a procedural scene (indoor floor or outdoor site) from a seed");
  scenegen->add_option("--family", scenegen_options.family, "indoor | outdoor");
  scenegen->add_option("--seed", scenegen_options.seed, "the seed, an integer >= 0");
  scenegen->add_option("--out", scenegen_options.out_dir,
                       "folder to write <family>_<seed>.yaml to");

  scancrew::cli::EvalOptions eval_options;
  auto* eval = app.add_subcommand(
      "eval", "score a reconstructed mesh against a scene's ground truth: coverage, error");
  eval->add_option("--mesh", eval_options.mesh_path, "reconstructed mesh (.ply)")->required();
  eval->add_option("--scene", eval_options.scene_path, "scene file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  eval->add_option("--voxel", eval_options.voxel_size_m,
                   "voxel size r_v, m; e_max = r_v*sqrt(3)/2 (default 0.2)")
      ->check(CLI::Range(1e-4, 100.0));
  eval->add_option("--density", eval_options.density_per_m2,
                   "ground-truth points per m2 (default 10000)");
  eval->add_option("--seed", eval_options.seed, "ground-truth random seed (default 1)");
  eval->add_option("--visibility-rays", eval_options.visibility_rays,
                   "ground truth: ray directions per point of the mesh visibility test, 0: off "
                   "(default 64)")
      ->check(CLI::Range(0, 100000));
  eval->add_option("--missed", eval_options.missed_path,
                   "write the ground-truth points not covered to this PLY (with normals)");
  eval->add_flag("--json", eval_options.json, "print one JSON object");

  scancrew::cli::KeysOptions keys_options;
  auto* keys = app.add_subcommand("keys", "a team's keys for DDS-Security (docs/security.md)");
  keys->require_subcommand(1);
  auto* keys_init = keys->add_subcommand("init", "make a team's authority and governance");
  keys_init->add_option("dir", keys_options.dir, "key folder (made if absent)")->required();
  keys_init->add_option("--team", keys_options.team, "the team's name (default: team)");
  auto* keys_add = keys->add_subcommand(
      "add", "make a place's identity and permissions (from the launch file's bridges)");
  keys_add->add_option("dir", keys_options.dir, "key folder (scancrew keys init)")->required();
  keys_add->add_option("launch", keys_options.launch, "the team's launch file")->required();
  auto* keys_robot = keys_add->add_option("--robot", keys_options.robot, "a robot, by its id")
                         ->check(CLI::Range(int64_t{1}, int64_t{4294967294}));
  auto* keys_station = keys_add->add_flag("--station", keys_options.station, "the ground station");
  auto* keys_sim = keys_add->add_flag("--sim", keys_options.sim, "the simulator");
  keys_robot->excludes(keys_station)->excludes(keys_sim);
  keys_station->excludes(keys_sim);
  keys_add
      ->add_option("--set", keys_options.overrides,
                   "name.key=value: a launch override, as the place runs with it (a "
                   "bridge's topics)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);

  std::string report_dir;
  auto* report = app.add_subcommand(
      "report", "write a mission run directory's pictures and report.html (docs/missions.md)");
  report->add_option("run_dir", report_dir, "run directory (scancrew run ... --out DIR)")
      ->required();

  auto* bench = app.add_subcommand("bench", "benchmarks");
  bench->require_subcommand(1);
  auto* ipc =
      bench->add_subcommand("ipc", "publish -> callback latency: scancrew vs Fast DDS and iceoryx");
  bool json = false;
  int samples = 2000;
  ipc->add_flag("--json", json, "print one JSON object");
  ipc->add_option("--samples", samples, "messages per case")->check(CLI::Range(10, 1000000));
  int spin_us = 0;
  ipc->add_option("--spin-us", spin_us, "scancrew receiver: spin before blocking, us")
      ->check(CLI::Range(0, 100000));
  std::string fastdds_intraprocess = "full";
  ipc->add_option(
         "--fastdds-intraprocess", fastdds_intraprocess,
         "Fast DDS intra-process delivery: full (library default) or off (data-sharing path)")
      ->check(CLI::IsMember({"full", "off"}));

  scancrew::bench::SimBenchOptions sim_bench;
  auto* sim_cmd =
      bench->add_subcommand("sim", "simulator: render time per stereo pair, real-time factor");
  sim_cmd->add_flag("--json", sim_bench.json, "print one JSON object");
  sim_cmd->add_option("--scene", sim_bench.scene_path, "scene file")->check(CLI::ExistingFile);
  sim_cmd->add_option("--renders", sim_bench.renders, "stereo pairs timed per size")
      ->check(CLI::Range(5, 100000));
  sim_cmd->add_option("--sim-seconds", sim_bench.sim_seconds, "simulated seconds per case")
      ->check(CLI::Range(0.1, 3600.0));

  scancrew::bench::PerceptionBenchOptions perception_bench;
  auto* perception_cmd = bench->add_subcommand(
      "perception", "stereo depth and VIO on a recorded parking-lot sequence: time and error");
  perception_cmd->add_flag("--json", perception_bench.json, "print one JSON object");
  perception_cmd->add_option("--scene", perception_bench.scene_path, "scene to record in")
      ->check(CLI::ExistingFile);
  perception_cmd
      ->add_option("--recording", perception_bench.recording,
                   "play this .sclog (stereo, imu, pose_gt, depth_gt) instead of recording one")
      ->check(CLI::ExistingFile);
  perception_cmd->add_option("--keep", perception_bench.keep,
                             "write the recording made to this path and keep it");
  perception_cmd
      ->add_option("--distance", perception_bench.distance_m, "metres to drive (default 62)")
      ->check(CLI::Range(0.5, 10000.0));
  perception_cmd
      ->add_option("--rpe-segment", perception_bench.rpe_segment_m,
                   "RPE segment length, m (default 10)")
      ->check(CLI::Range(0.1, 10000.0));
  perception_cmd->add_option("--width", perception_bench.width, "image width (default 320)")
      ->check(CLI::Range(64u, 1920u));
  perception_cmd->add_option("--height", perception_bench.height, "image height (default 256)")
      ->check(CLI::Range(64u, 1080u));
  perception_cmd->add_option("--seed", perception_bench.seed, "simulator seed (default 1)");

  scancrew::bench::TsdfBenchOptions tsdf_bench;
  auto* tsdf_cmd = bench->add_subcommand(
      "tsdf", "TSDF integration and meshing: time, memory, accuracy; scancrew vs Open3D");
  tsdf_cmd->add_flag("--json", tsdf_bench.json, "print one JSON object");
  tsdf_cmd->add_option("--scene", tsdf_bench.scene_path, "scene to render in")
      ->check(CLI::ExistingFile);
  tsdf_cmd
      ->add_option("--frames", tsdf_bench.frames,
                   "depth frames per resolution (default 60; 10 with --quick)")
      ->check(CLI::Range(1, 100000));
  tsdf_cmd->add_flag("--quick", tsdf_bench.quick,
                     "320x256, voxel 0.2 m, range 5 m, 10 frames only (smoke test)");
  tsdf_cmd
      ->add_option("--repeat", tsdf_bench.repeats,
                   "runs per system and configuration; the fastest is reported (default 5)")
      ->check(CLI::Range(1, 100));
  tsdf_cmd
      ->add_option("--density", tsdf_bench.density_per_m2,
                   "ground-truth points per m2 (default 2000)")
      ->check(CLI::Range(1.0, 100000.0));
  tsdf_cmd->add_option("--seed", tsdf_bench.seed, "depth noise and ground-truth seed (default 1)");
  tsdf_cmd
      ->add_option("--weight", tsdf_bench.weight,
                   "scancrew's measurement weight (default: the TsdfConfig's, inverse_square)")
      ->check(CLI::IsMember({"inverse_square", "constant"}));
  tsdf_cmd
      ->add_option("--w-th", tsdf_bench.w_th, "scancrew's known-voxel weight W_th (default 0.3)")
      ->check(CLI::Range(1e-6, 1000.0));
  tsdf_cmd
      ->add_option("--mesh-min-weight", tsdf_bench.mesh_min_weight,
                   "weight from which the mesher counts a voxel observed (default: MesherConfig's)")
      ->check(CLI::Range(1e-9, 1000.0));
  tsdf_cmd->add_option("--sizes", tsdf_bench.sizes, "image sizes, e.g. 640x480 (default both)")
      ->delimiter(',');
  tsdf_cmd->add_option("--voxels", tsdf_bench.voxels_m, "voxel sizes in m (default 0.1,0.2,0.3)")
      ->delimiter(',')
      ->check(CLI::Range(0.01, 2.0));
  tsdf_cmd->add_option("--ranges", tsdf_bench.ranges_m, "depth ranges in m (default 5,8)")
      ->delimiter(',')
      ->check(CLI::Range(0.5, 50.0));

  scancrew::bench::IseBenchOptions ise_bench;
  auto* ise_cmd = bench->add_subcommand(
      "ise", "ISE extraction, viewpoints, clusters and gain: incremental and full update time");
  ise_cmd->add_flag("--json", ise_bench.json, "print one JSON object");
  ise_cmd
      ->add_option("--frames", ise_bench.frames,
                   "depth frames per scene (default 300 parking lot, 1000 powerplant)")
      ->check(CLI::Range(1, 100000));
  ise_cmd->add_flag(
      "--quick", ise_bench.quick,
      "80 parking-lot frames, a tenth of the powerplant lap, one full() (smoke test)");
  ise_cmd
      ->add_option("--repeat", ise_bench.repeats,
                   "full() calls per scene; the fastest is reported (default 3)")
      ->check(CLI::Range(1, 100));
  ise_cmd
      ->add_option("--warmup", ise_bench.warmup,
                   "first updates left out of the incremental figures (default 3)")
      ->check(CLI::Range(0, 1000));
  ise_cmd->add_option("--seed", ise_bench.seed, "depth noise seed (default 1)");
  ise_cmd->add_option("--scenes", ise_bench.scenes, "parking_lot, powerplant (default both)")
      ->delimiter(',')
      ->check(CLI::IsMember({"parking_lot", "powerplant"}));

  scancrew::bench::TspBenchOptions tsp_bench;
  auto* tsp_cmd = bench->add_subcommand(
      "tsp", "(max)ATSP solver: TSPLIB gap and time per instance, maxATSP time on 50-200 clusters");
  tsp_cmd->add_flag("--json", tsp_bench.json, "print one JSON object");
  tsp_cmd
      ->add_option("--dir", tsp_bench.dir,
                   "folder of the TSPLIB .atsp files (default data/tsplib_atsp)")
      ->check(CLI::ExistingDirectory);
  tsp_cmd->add_flag("--quick", tsp_bench.quick,
                    "br17, ftv33, ftv38 and two maxATSP instances per size (smoke test)");
  tsp_cmd->add_option("--seed", tsp_bench.seed, "solver seed (default 1)");
  tsp_cmd
      ->add_option("--kicks-per-node", tsp_bench.kicks_per_node,
                   "TSPLIB iteration budget: kicks per node (default 500)")
      ->check(CLI::Range(1, 1000000));
  tsp_cmd->add_option("--repeat", tsp_bench.repeats, "maxATSP instances per size (default 5)")
      ->check(CLI::Range(1, 1000));

  scancrew::bench::PlannerBenchOptions planner_bench;
  auto* planner_cmd = bench->add_subcommand(
      "planner", "low-level planner (LazyPRM*): query time, first query and reused roadmap");
  planner_cmd->add_flag("--json", planner_bench.json, "print one JSON object");
  planner_cmd
      ->add_option("--frames", planner_bench.frames,
                   "frames per scene (default 300 parking lot, 1000 powerplant)")
      ->check(CLI::Range(1, 100000));
  planner_cmd
      ->add_option("--queries", planner_bench.queries, "reused-roadmap queries per scene (100)")
      ->check(CLI::Range(1, 100000));
  planner_cmd->add_option("--firsts", planner_bench.firsts, "first queries, fresh planners (10)")
      ->check(CLI::Range(1, 10000));
  planner_cmd->add_flag("--quick", planner_bench.quick,
                        "80 + 100 frames, 20 + 3 queries per scene (smoke test)");
  planner_cmd->add_option("--seed", planner_bench.seed, "depth noise, queries, OMPL (default 1)");
  planner_cmd
      ->add_option("--scenes", planner_bench.scenes, "parking_lot, powerplant (default both)")
      ->delimiter(',')
      ->check(CLI::IsMember({"parking_lot", "powerplant"}));

  scancrew::bench::DdsBenchOptions dds_bench;
  auto* dds_cmd = bench->add_subcommand(
      "dds",
      "team network: latency and throughput with and without DDS-Security, the bridge and "
      "Fast DDS side by side");
  dds_cmd->add_flag("--json", dds_bench.json, "print one JSON object");
  dds_cmd->add_option("--samples", dds_bench.samples, "latency messages per case (1000)")
      ->check(CLI::Range(10, 1000000));
  dds_cmd->add_flag("--quick", dds_bench.quick,
                    "64 B and 64 KiB, 100 messages per case, a burst of 100 (smoke test)");
  dds_cmd
      ->add_option("--window", dds_bench.window,
                   "throughput: messages unreceived at most (default: the depth, 50)")
      ->check(CLI::Range(1, 50));
  dds_cmd
      ->add_option("--bridge-poll-s", dds_bench.bridge_poll_period_s,
                   "the bridges' import poll period, s (their default: 0.002)")
      ->check(CLI::Range(1e-4, 1.0));

  scancrew::bench::PipelineBenchOptions pipeline_bench;
  auto* pipeline_cmd = bench->add_subcommand(
      "pipeline",
      "one robot's graph on the wall clock: latency per stage and end to end, highest camera "
      "rate without dropped frames");
  pipeline_cmd->add_flag("--json", pipeline_bench.json, "print one JSON object");
  pipeline_cmd->add_flag("--quick", pipeline_bench.quick,
                         "12 pairs per trial, 2 search trials per size (smoke test)");
  pipeline_cmd->add_option("--launch", pipeline_bench.launch_path, "the graph (launch file)")
      ->check(CLI::ExistingFile);
  pipeline_cmd->add_option("--scene", pipeline_bench.scene_path, "scene to render the pairs in")
      ->check(CLI::ExistingFile);
  pipeline_cmd->add_option("--sizes", pipeline_bench.sizes, "image sizes (default 320x256,640x480)")
      ->delimiter(',');
  pipeline_cmd->add_option("--frames", pipeline_bench.frames, "stereo pairs per trial (100)")
      ->check(CLI::Range(2, 100000));
  pipeline_cmd->add_option("--rate", pipeline_bench.nominal_rate_hz, "nominal camera rate, Hz (5)")
      ->check(CLI::Range(0.1, 1000.0));
  pipeline_cmd->add_option("--threads", pipeline_bench.threads, "executor threads (2)")
      ->check(CLI::Range(1, 64));
  pipeline_cmd->add_option("--trials", pipeline_bench.max_trials, "rate-search trials per size (8)")
      ->check(CLI::Range(1, 100));
  pipeline_cmd->add_option("--set", pipeline_bench.sets,
                           "override a launch parameter: name.key=value (as scancrew run --set)");
  pipeline_cmd->add_option("--seed", pipeline_bench.seed, "simulator seed (default 1)");

  scancrew::cli::ExploreOptions explore_bench;
  auto* explore_cmd = bench->add_subcommand(
      "explore",
      "the exploration benchmark: thesis and procedural scenes x teams x architectures, "
      "compute charged, default parameters (docs/results/explore.md)");
  explore_cmd->add_flag("--json", explore_bench.json, "print every run and the rows as JSON");
  explore_cmd->add_flag("--quick", explore_bench.quick,
                        "2 small procedural scenes, short budgets (CI); checks the metrics");
  explore_cmd->add_option("--jobs", explore_bench.jobs, "runs at a time (default: the cores)")
      ->check(CLI::Range(1, 64));
  explore_cmd->add_option("--out", explore_bench.out_dir,
                          "output folder (runs/bench_explore); a rerun resumes it");
  explore_cmd
      ->add_option("--only", explore_bench.only,
                   "only the runs whose name (<scene>_<architecture>_r<robots>) contains one of "
                   "these, comma-separated (e.g. powerplant_,indoor_1_centralized)")
      ->delimiter(',');
  explore_cmd->add_flag("--report", explore_bench.report,
                        "write the tables of the runs already done under --out; start none");

  CLI11_PARSE(app, argc, argv);

  if (explore_cmd->parsed()) return scancrew::cli::run_explore_bench(explore_bench);

  if (run->parsed()) return scancrew::cli::run_launch(run_options);
  if (keys_init->parsed()) return scancrew::cli::run_keys_init(keys_options);
  if (keys_add->parsed()) return scancrew::cli::run_keys_add(keys_options);
  for (auto [cmd, process] : {std::pair{sim_part, "sim"}, std::pair{robot_part, "robot"},
                              std::pair{station_part, "station"}})
    if (cmd->parsed()) {
      part_options.process = process;
      return scancrew::cli::run_launch(part_options);
    }
  if (sweep->parsed()) return scancrew::cli::run_sweep(sweep_options);
  if (components->parsed()) return cmd_components();
  if (graph->parsed()) return cmd_graph(graph_path);
  if (render->parsed()) return scancrew::cli::run_render(render_options);
  if (groundtruth->parsed()) return scancrew::cli::run_groundtruth(gt_options);
  if (scenegen->parsed()) return scancrew::cli::run_scenegen(scenegen_options);
  if (eval->parsed()) return scancrew::cli::run_eval(eval_options);
  if (report->parsed()) return cmd_report(report_dir);
  if (sim_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_sim_bench(sim_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (tsdf_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_tsdf_bench(tsdf_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (ise_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_ise_bench(ise_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (planner_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_planner_bench(planner_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (tsp_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_tsp_bench(tsp_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (dds_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_dds_bench(dds_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (pipeline_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_pipeline_bench(pipeline_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (perception_cmd->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_perception_bench(perception_bench);
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  if (ipc->parsed()) {
#ifdef SCANCREW_WITH_BENCH
    return scancrew::bench::run_ipc_bench({.samples = samples,
                                           .json = json,
                                           .spin_us = spin_us,
                                           .fastdds_intraprocess = fastdds_intraprocess == "full"});
#else
    std::fprintf(stderr, "scancrew: built without benchmarks (SCANCREW_BUILD_BENCH=OFF)\n");
    return 2;
#endif
  }
  return 1;
}
