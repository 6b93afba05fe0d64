#include "cli/explore_bench.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <thread>

#include "cli/child_process.hpp"
#include "cli/commands.hpp"
#include "cli/explore_table.hpp"
#include "cli/explore_targets.hpp"
#include "cli/mission_compose.hpp"
#include "cli/thesis_table.hpp"
#include "executors/log.hpp"
#include "executors/params_impl.hpp"
#include "scenegen/scenegen.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_stop = 0;

void on_signal(int /*signal*/) {
  g_stop = 1;
  static constexpr char kMessage[] =
      "\nscancrew bench explore: stopping after the runs in progress (rerun to resume)\n";
  const ssize_t written = write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  (void)written;
}

struct BenchScene {
  std::string name, family, path;
  robot::RobotKind kind = robot::RobotKind::kGround;
  double budget_s = 0;
};

// The benchmark's scene sizes (so that it fits in 2 hours on 2 cores): procedural scenes of at
// most this floor area, and their budgets (simulated seconds, compute charged).
constexpr double kIndoorMaxAreaM2 = 625;    // 25 x 25 m
constexpr double kOutdoorMaxAreaM2 = 3600;  // 60 x 60 m
constexpr double kIndoorBudgetS = 600, kOutdoorBudgetS = 600;
constexpr double kQuickBudgetS = 150;        // the multirotor's smoke run
constexpr double kQuickMinReachable = 0.95;  // the ground pair's (issue: Step 11)

double floor_area_m2(const sim::SceneSpec& s) {
  return (s.max_m.x - s.min_m.x) * (s.max_m.y - s.min_m.y);
}

// Writes the scene of (family, seed) under dir (kept if there, byte for byte the same).
Result<BenchScene, std::string> procedural_scene(scenegen::Family family, uint64_t seed,
                                                 const fs::path& dir, double budget_s) {
  auto g = scenegen::generate(family, seed);
  if (!g) return make_unexpected(g.error());
  const std::string name = scenegen::to_string(family) + "_" + std::to_string(seed);
  const fs::path path = dir / (name + ".yaml");
  const std::string text = scenegen::write_scene_yaml(
      g->scene, "scancrew scenegen --family " + scenegen::to_string(family) + " --seed " +
                    std::to_string(seed));
  if (const auto old = read_text_file(path.string()); !old || *old != text) {
    std::ofstream f(path);
    f << text;
    if (!f) return make_unexpected("cannot write " + path.string());
  }
  return BenchScene{.name = name,
                    .family = scenegen::to_string(family),
                    .path = path.string(),
                    .kind = scenegen::robot_kind(family),
                    .budget_s = budget_s};
}

// The first `count` seeds from 1 whose scene's floor is at most max_area_m2 (quick: the one
// smallest of seeds 1-20).
Result<std::vector<BenchScene>, std::string> procedural_scenes(scenegen::Family family, bool quick,
                                                               const fs::path& dir) {
  const double max_area =
      family == scenegen::Family::kIndoor ? kIndoorMaxAreaM2 : kOutdoorMaxAreaM2;
  const double budget = family == scenegen::Family::kIndoor
                            ? kIndoorBudgetS
                            : (quick ? kQuickBudgetS : kOutdoorBudgetS);
  std::vector<uint64_t> seeds;
  if (quick) {
    uint64_t best = 0;
    double best_area = 0;
    for (uint64_t seed = 1; seed <= 20; ++seed) {
      auto g = scenegen::generate(family, seed);
      if (!g) continue;
      if (best == 0 || floor_area_m2(g->scene) < best_area) {
        best = seed;
        best_area = floor_area_m2(g->scene);
      }
    }
    if (best == 0)
      return make_unexpected("no " + scenegen::to_string(family) + " scene of seeds 1-20");
    seeds.push_back(best);
  } else {
    for (uint64_t seed = 1; seed <= 200 && seeds.size() < 4; ++seed) {
      auto g = scenegen::generate(family, seed);
      if (g && floor_area_m2(g->scene) <= max_area) seeds.push_back(seed);
    }
    if (seeds.size() < 4)
      return make_unexpected("fewer than 4 " + scenegen::to_string(family) +
                             " scenes of seeds 1-200 fit the benchmark");
  }
  std::vector<BenchScene> scenes;
  for (const uint64_t seed : seeds) {
    auto s = procedural_scene(family, seed, dir, budget);
    if (!s) return make_unexpected(s.error());
    scenes.push_back(std::move(s).value());
  }
  return scenes;
}

std::vector<ExploreRun> plan_runs(const std::vector<BenchScene>& scenes, bool quick,
                                  const fs::path& out) {
  std::vector<ExploreRun> runs;
  for (const BenchScene& s : scenes) {
    const bool ground = s.kind == robot::RobotKind::kGround;
    std::vector<size_t> teams =
        ground ? std::vector<size_t>{1, 2, 4} : std::vector<size_t>{1, 3, 5};
    // quick: the ground pair, both architectures, asserted complete (run_explore_bench);
    // the one multirotor on a short budget, a smoke run: no UAV run completes yet
    if (quick) teams = ground ? std::vector<size_t>{2} : std::vector<size_t>{1};
    for (const size_t n : teams)
      for (const auto& [arch, arch_name] : kArchitectureNames) {
        if ((n == 1) != (arch == Architecture::kSingle)) continue;
        ExploreRun r{.scene = s.name,
                     .family = s.family,
                     .kind = s.kind,
                     .arch = arch,
                     .robots = n,
                     .budget_s = s.budget_s};
        r.run_dir =
            (out / "runs" / (s.name + "_" + std::string(arch_name) + "_r" + std::to_string(n)))
                .string();
        runs.push_back(std::move(r));
      }
  }
  return runs;
}

// A run done before (resume): its exit status and metrics.json. A run not done stays as it was.
bool read_done(ExploreRun& r) {
  const auto status = read_text_file((fs::path(r.run_dir) / "exit_status").string());
  if (!status) return false;
  const int exit_status = std::atoi(status->c_str());
  if (exit_status != 0 && exit_status != 3) return false;  // failed or interrupted: again
  const auto text = read_text_file((fs::path(r.run_dir) / "metrics.json").string());
  if (!text) return false;
  auto read = read_explore_metrics(*text, r, r.run_dir + "/metrics.json");
  if (!read || read->stop_reason == StopReason::kInterrupted) return false;
  r = std::move(read).value();
  r.exit_status = exit_status;
  return true;
}

void finish_run(ExploreRun& r, int status) {
  r.exit_status = status;
  std::ofstream((fs::path(r.run_dir) / "exit_status").string()) << status << "\n";
  const fs::path metrics = fs::path(r.run_dir) / "metrics.json";
  if (const auto text = read_text_file(metrics.string())) {
    auto read = read_explore_metrics(*text, r, metrics.string());
    if (read)
      r = std::move(read).value();
    else
      r.error = read.error();
  } else {
    r.error = "no metrics.json (exit status " + std::to_string(status) + "; see " + r.run_dir +
              "/run.log)";
  }
}

std::string describe(const ExploreRun& r) {
  if (!r.ran()) return "failed: " + r.error;
  char buf[200];
  std::snprintf(
      buf, sizeof buf, "%s at %.1f s, coverage %.1f %% (%.1f %% of the reachable), %.0f s wall",
      to_string(r.stop_reason).c_str(), r.completed() ? r.completion_time_s : r.sim_time_s,
      100 * r.coverage, 100 * r.coverage_reachable, r.wall_time_s);
  return buf;
}

std::string machine_line() {
  char host[256] = "?";
  gethostname(host, sizeof host);
  return std::to_string(std::thread::hardware_concurrency()) + " cores (" + host + ")";
}

// The planning map's voxel of a robot kind: its profile's tsdf_mapper.voxel_m (the missions are
// composed from it), else the thesis's (0.1 m as our ground missions, 0.3 m).
TargetVoxels profile_voxels() {
  TargetVoxels v;
  for (const auto& [kind, kind_name] : robot::kRobotKindNames) {
    double& voxel = kind == robot::RobotKind::kGround ? v.ground_m : v.multirotor_m;
    const std::string name(kind_name);
    const auto text = read_text_file("launch_cfg/profiles/" + name + ".yaml");
    if (!text) continue;
    const auto root = parse_yaml(*text, name);
    if (!root || !root->IsMap()) continue;
    const YAML::Node value = (*root)["tsdf_mapper"]["voxel_m"];
    try {
      if (value.IsDefined() && value.IsScalar()) voxel = value.as<double>();
    } catch (const YAML::Exception&) {  // not a number: the composed missions refuse it anyway
    }
  }
  return v;
}

// The benchmark's scenes, thesis and procedural (the latter written under out/scenes).
Result<std::vector<BenchScene>, std::string> bench_scenes(bool quick, const fs::path& out) {
  std::vector<BenchScene> scenes;
  if (!quick) {
    using robot::RobotKind;
    scenes.push_back(
        {"arena", "arena", "launch_cfg/scenes/test_arena.yaml", RobotKind::kGround, 240});
    scenes.push_back({"parking_lot", "parking_lot", "launch_cfg/scenes/parking_lot.yaml",
                      RobotKind::kGround, 1500});
    scenes.push_back({"powerplant", "powerplant", "launch_cfg/scenes/powerplant.yaml",
                      RobotKind::kMultirotor, 900});
  }
  for (const auto family : {scenegen::Family::kIndoor, scenegen::Family::kOutdoor}) {
    auto more = procedural_scenes(family, quick, out / "scenes");
    if (!more) return make_unexpected(more.error());
    scenes.insert(scenes.end(), more->begin(), more->end());
  }
  // the ground robots' scenes first, the powerplant last: a benchmark stopped early (and
  // resumed later) has the cheaper rows filled
  std::stable_partition(scenes.begin(), scenes.end(),
                        [](const BenchScene& s) { return s.kind == robot::RobotKind::kGround; });
  std::stable_partition(scenes.begin(), scenes.end(),
                        [](const BenchScene& s) { return s.name != "powerplant"; });
  return scenes;
}

// Keeps the runs whose directory name contains one of `only`'s parts.
void keep_only(std::vector<ExploreRun>& runs, const std::vector<std::string>& only) {
  std::erase_if(runs, [&](const ExploreRun& r) {
    const std::string name = fs::path(r.run_dir).filename().string();
    return std::none_of(only.begin(), only.end(), [&](const std::string& part) {
      return name.find(part) != std::string::npos;
    });
  });
}

// The command line that reproduces this benchmark, for the tables.
std::string bench_command(const ExploreOptions& o) {
  std::string only;
  for (const std::string& part : o.only) only += (only.empty() ? "" : ",") + part;
  return std::string("scancrew bench explore") + (o.quick ? " --quick" : "") +
         (o.jobs > 0 ? " --jobs " + std::to_string(o.jobs) : "") +
         (o.out_dir.empty() ? "" : " --out " + o.out_dir) + (only.empty() ? "" : " --only " + only);
}

// Wall minutes since t0.
double minutes_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 60;
}

// Starts one run as a child process: its pid, or -1 with r.error saying why not.
pid_t start_run(ExploreRun& r, const std::string& scene_path,
                std::chrono::steady_clock::time_point t0) {
  std::error_code ec;
  fs::create_directories(r.run_dir, ec);
  fs::remove(fs::path(r.run_dir) / "metrics.json", ec);
  fs::remove(fs::path(r.run_dir) / "run.log", ec);
  auto launch = compose_mission({.scene_path = scene_path,
                                 .kind = r.kind,
                                 .robots = r.robots,
                                 .arch = r.arch,
                                 .duration_s = r.budget_s});
  if (!launch) {
    r.error = launch.error();
    std::fprintf(stderr, "[%5.1f min] %s %s %zu: not started: %s\n", minutes_since(t0),
                 r.scene.c_str(), to_string(r.arch).c_str(), r.robots, r.error.c_str());
    return -1;
  }
  const std::string launch_path = (fs::path(r.run_dir) / "launch.yaml").string();
  std::ofstream(launch_path) << *launch;
  const pid_t pid =
      start_child({"scancrew", "run", launch_path, "--out", r.run_dir, "--trace-events", "0"},
                  (fs::path(r.run_dir) / "run.log").string());
  if (pid < 0) {
    r.error = "could not start scancrew run";
    return -1;
  }
  std::fprintf(stderr, "[%5.1f min] start  %s %s %zu (%s)\n", minutes_since(t0), r.scene.c_str(),
               to_string(r.arch).c_str(), r.robots, r.run_dir.c_str());
  return pid;
}

// What run_all did: the runs done, and of them those an earlier benchmark had done.
struct RunCounts {
  size_t done = 0, resumed = 0;
};

// Runs the runs not done before, `jobs` at a time, tables after each, until done or stopped.
RunCounts run_all(std::vector<ExploreRun>& runs, const std::vector<BenchScene>& scenes, size_t jobs,
                  std::chrono::steady_clock::time_point t0,
                  const std::function<void()>& write_tables) {
  std::map<std::string, std::string> scene_path;
  for (const BenchScene& s : scenes) scene_path[s.name] = s.path;
  std::map<pid_t, size_t> running;
  size_t next = 0;
  RunCounts counts;
  const auto start_next = [&]() -> bool {
    for (; next < runs.size(); ++next) {
      ExploreRun& r = runs[next];
      if (read_done(r)) {
        ++counts.done;
        ++counts.resumed;
        continue;
      }
      const pid_t pid = start_run(r, scene_path[r.scene], t0);
      if (pid < 0) {
        ++counts.done;
        continue;
      }
      running[pid] = next++;
      return true;
    }
    return false;
  };
  while (g_stop == 0 && running.size() < jobs && start_next()) {
  }
  while (!running.empty()) {
    const auto [pid, status] = wait_any_child();
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    ExploreRun& r = runs[it->second];
    running.erase(it);
    finish_run(r, status);
    ++counts.done;
    std::fprintf(stderr, "[%5.1f min] %zu/%zu  %s %s %zu: %s\n", minutes_since(t0), counts.done,
                 runs.size(), r.scene.c_str(), to_string(r.arch).c_str(), r.robots,
                 describe(r).c_str());
    write_tables();
    while (g_stop == 0 && running.size() < jobs && start_next()) {
    }
  }
  return counts;
}

// --quick's checks of the runs: 0 when they pass, else 1 (each problem printed).
int check_quick_runs(const std::vector<ExploreRun>& runs) {
  size_t bad = 0;
  for (const ExploreRun& r : runs)
    if (const std::string problem = check_explore_run(r); !problem.empty()) {
      std::fprintf(stderr, "scancrew bench explore --quick: %s\n", problem.c_str());
      ++bad;
    }
  // the ground pair must finish the job: the ISE criterion within the budget, 95 % of
  // the reachable surface, no contact
  size_t asserted = 0;
  for (const ExploreRun& r : runs) {
    if (r.kind != robot::RobotKind::kGround) continue;
    ++asserted;
    const std::string who =
        r.scene + " " + to_string(r.arch) + " " + std::to_string(r.robots) + ": ";
    char problem[128] = "";
    if (!r.completed())
      std::snprintf(problem, sizeof problem, "did not complete (%s)",
                    to_string(r.stop_reason).c_str());
    else if (!(r.coverage_reachable >= kQuickMinReachable))
      std::snprintf(problem, sizeof problem, "reachable coverage %.1f %% < %.0f %%",
                    100 * r.coverage_reachable, 100 * kQuickMinReachable);
    else if (r.contacts != 0)
      std::snprintf(problem, sizeof problem, "%.0f contacts", r.contacts);
    if (problem[0] != '\0') {
      std::fprintf(stderr, "scancrew bench explore --quick: %s%s\n", who.c_str(), problem);
      ++bad;
    }
  }
  if (asserted == 0) {
    std::fprintf(stderr, "scancrew bench explore --quick: no ground run to assert\n");
    ++bad;
  }
  if (bad > 0) return 1;
  std::fprintf(stderr,
               "scancrew bench explore --quick: %zu runs, metrics consistent; %zu ground runs "
               "complete, >= 95 %% of the reachable surface, 0 contacts\n",
               runs.size(), asserted);
  return 0;
}

}  // namespace

int run_explore_bench(const ExploreOptions& o) {
  const fs::path out = o.out_dir.empty()
                           ? fs::path(o.quick ? "runs/bench_explore_quick" : "runs/bench_explore")
                           : fs::path(o.out_dir);
  std::error_code ec;
  fs::create_directories(out / "scenes", ec);
  fs::create_directories(out / "runs", ec);
  if (ec) {
    std::fprintf(stderr, "scancrew bench explore: cannot create %s: %s\n", out.c_str(),
                 ec.message().c_str());
    return 2;
  }
  const auto scenes = bench_scenes(o.quick, out);
  if (!scenes) {
    std::fprintf(stderr, "scancrew bench explore: %s\n",
                 scancrew::log::printable(scenes.error()).c_str());
    return 2;
  }
  std::vector<ExploreRun> runs = plan_runs(*scenes, o.quick, out);
  if (!o.only.empty()) {
    keep_only(runs, o.only);
    if (runs.empty()) {
      std::fprintf(stderr, "scancrew bench explore: --only matches no run\n");
      return 2;
    }
  }

  const size_t jobs = o.jobs > 0 ? o.jobs : std::max(1u, std::thread::hardware_concurrency());
  const std::string command = bench_command(o);
  const std::string title = std::string("bench explore") + (o.quick ? " --quick" : "") + ": " +
                            std::to_string(runs.size()) + " runs";
  // the family table, and (the thesis's scenes are in the full set only) the thesis's rows
  const auto markdown = [&] {
    return format_explore_markdown(runs, title, command, machine_line()) +
           (o.quick ? ""
                    : "\n" + format_targets_markdown(explore_targets(runs, profile_voxels())) +
                          "\n" + format_thesis_markdown(runs));
  };
  const auto write_tables = [&] {
    std::ofstream(out / "explore.csv") << format_explore_csv(runs);
    std::ofstream(out / "explore.md") << markdown();
  };

  if (o.report) {
    size_t found = 0;
    for (ExploreRun& r : runs) found += read_done(r) ? 1 : 0;
    write_tables();
    std::printf("%s", o.json ? format_explore_json(runs).c_str() : markdown().c_str());
    std::fprintf(stderr, "%zu of %zu runs done under %s; %s, %s\n", found, runs.size(), out.c_str(),
                 (out / "explore.md").c_str(), (out / "explore.csv").c_str());
    return 0;
  }

  g_stop = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const auto t0 = std::chrono::steady_clock::now();
  const RunCounts counts = run_all(runs, *scenes, jobs, t0, write_tables);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  write_tables();
  if (o.json)
    std::printf("%s", format_explore_json(runs).c_str());
  else
    std::printf("%s", markdown().c_str());
  std::fprintf(stderr, "%zu of %zu runs done (%zu from an earlier run) in %.1f min; %s, %s\n",
               counts.done, runs.size(), counts.resumed, minutes_since(t0),
               (out / "explore.md").c_str(), (out / "explore.csv").c_str());
  if (g_stop != 0 || counts.done < runs.size()) return 1;
  if (o.quick) return check_quick_runs(runs);
  return 0;
}

void add_explore_command(CLI::App& bench, CommandTable& table) {
  auto [explore, o] = table.add_with_options<ExploreOptions>(
      bench, "explore",
      "the exploration benchmark: thesis and procedural scenes x teams x architectures, "
      "compute charged, default parameters (docs/results/explore.md)",
      run_explore_bench);
  explore->add_flag("--json", o->json, "print every run and the rows as JSON");
  explore->add_flag("--quick", o->quick,
                    "2 small procedural scenes, short budgets (CI); checks the metrics");
  explore->add_option("--jobs", o->jobs, "runs at a time (default: the cores)")
      ->check(CLI::Range(1, 64));
  explore->add_option("--out", o->out_dir,
                      "output folder (runs/bench_explore); a rerun resumes it");
  explore
      ->add_option("--only", o->only,
                   "only the runs whose name (<scene>_<architecture>_r<robots>) contains one of "
                   "these, comma-separated (e.g. powerplant_,indoor_1_centralized)")
      ->delimiter(',');
  explore->add_flag("--report", o->report,
                    "write the tables of the runs already done under --out; start none");
}

}  // namespace scancrew::cli
