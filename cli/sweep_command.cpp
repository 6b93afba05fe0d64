#include "cli/sweep_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "cli/child_process.hpp"
#include "cli/commands.hpp"
#include "cli/mission_compose.hpp"
#include "cli/sweep_table.hpp"
#include "executors/log.hpp"
#include "executors/params_impl.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;

volatile std::sig_atomic_t g_stop = 0;
volatile pid_t g_child = 0;  // the `scancrew run` now running; 0: none

// Ctrl-C reaches the run too (the terminal signals the process group): it stops its mission
// and writes its run directory as "interrupted". A SIGTERM sent to the sweep alone is passed
// on to the run. The sweep stops after it.
void on_signal(int signal) {
  g_stop = 1;
  if (signal == SIGTERM && g_child > 0) kill(g_child, SIGTERM);
  static constexpr char kMessage[] = "\nscancrew sweep: stopping after the current run\n";
  const ssize_t written = write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  (void)written;
}

struct SweepPlan {
  std::map<Architecture, std::string> launch_of;  // architecture -> launch file
  std::vector<std::string> seed_keys;
  bool sweep_file = false;
};

std::string join(const std::vector<std::string>& items, const char* separator = ", ") {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : separator) + i;
  return s;
}

// A sweep file (architectures: {arch: launch file}, seed_keys: [...]) or a plain launch file.
Result<SweepPlan, std::string> read_plan(const std::string& path) {
  const auto text = read_text_file(path);
  if (!text) return make_unexpected(path + ": cannot be read: " + text.error());
  auto root = parse_yaml(*text, path);
  if (!root) return make_unexpected(root.error());
  SweepPlan plan;
  if (!root->IsMap() || !(*root)["architectures"].IsDefined()) return plan;  // a launch file
  plan.sweep_file = true;
  ParamReader top = make_param_reader(*root, path, "(top level)");
  top.optional_list("seed_keys", plan.seed_keys);
  top.mark_known("architectures");
  top.finish();
  std::vector<std::string> errors = top.errors();
  const YAML::Node archs = (*root)["architectures"];
  if (!archs.IsMap() || archs.size() == 0)
    errors.push_back(yaml_location(path, archs) +
                     ": architectures: must map architectures (single, centralized, "
                     "distributed) to launch files");
  else
    for (const auto& kv : archs) {
      const std::string arch = kv.first.Scalar();
      // a launch file's path is relative to the sweep file's directory
      const std::string launch =
          kv.second.IsScalar() && !kv.second.Scalar().empty()
              ? (fs::path(path).parent_path() / kv.second.Scalar()).lexically_normal().string()
              : std::string();
      const auto value = value_of(kArchitectureNames, arch);
      if (!value)
        errors.push_back(yaml_location(path, kv.first) + ": architectures." + arch +
                         ": unknown architecture; allowed: " + joined_names(kArchitectureNames));
      else if (!kv.second.IsScalar() || kv.second.Scalar().empty())
        errors.push_back(yaml_location(path, kv.second) + ": architectures." + arch +
                         ": must be a launch file");
      else if (std::error_code ec; !fs::is_regular_file(launch, ec))
        errors.push_back(yaml_location(path, kv.second) + ": architectures." + arch + ": '" +
                         kv.second.Scalar() + "' is not a file (paths are relative to the " +
                         "sweep file's directory)");
      else
        plan.launch_of[*value] = launch;
    }
  if (!errors.empty()) return make_unexpected(join(errors, "\n  "));
  return plan;
}

// How many robots a launch file lists (1 without a robots: list, as Launch counts them), and
// how many it runs when not told (run.robots, else all); 0 if it cannot say. A mission file
// "lists" every team it composes (the scene's starts of its kind; scancrew run --robots N).
struct TeamSize {
  size_t listed = 0, runs = 0;
};
TeamSize team_size(const std::string& launch_path) {
  const auto text = launch_file_text(launch_path);  // a mission file: its composed graph
  if (!text) return {};
  const auto root = parse_yaml(*text, launch_path);
  if (!root || !root->IsMap()) return {};
  const YAML::Node robots = (*root)["robots"];
  TeamSize team{.listed = robots.IsDefined() && robots.IsSequence() ? robots.size() : 1};
  team.runs = team.listed;
  const YAML::Node run = (*root)["run"];
  const YAML::Node run_robots = run.IsDefined() && run.IsMap() ? run["robots"] : YAML::Node();
  if (run_robots.IsDefined() && run_robots.IsScalar()) {
    try {
      if (const auto n = run_robots.as<size_t>(); n > 0 && n <= team.listed) team.runs = n;
    } catch (const YAML::Exception&) {
      // Launch refuses it with its own message when the run starts
    }
  }
  if (const auto raw = read_text_file(launch_path)) {
    const auto raw_root = parse_yaml(*raw, launch_path);
    if (raw_root && raw_root->IsMap() && (*raw_root)["mission"].IsDefined())
      for (size_t n = team.listed + 1; n <= 64 && launch_file_text(launch_path, n); ++n)
        team.listed = n;
  }
  return team;
}

struct PlannedRun {
  Architecture arch = Architecture::kSingle;
  std::string launch;
  size_t robots = 0;
  int seed = 0;
};

std::string stem_of(const std::string& path) {
  std::string stem = fs::path(path).filename().string();
  stem = stem.substr(0, stem.find('.'));
  return stem.empty() ? "sweep" : stem;
}

bool write_file(const fs::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  file.close();
  if (!file) std::fprintf(stderr, "scancrew sweep: cannot write %s\n", path.c_str());
  return static_cast<bool>(file);
}

// Runs `scancrew run ARGS` in a child process (cli/child_process.hpp); its exit status.
int run_in_child(const std::vector<std::string>& args) {
  const pid_t pid = start_child(args);
  if (pid < 0) return 127;
  g_child = pid;
  const int status = wait_child(pid);
  g_child = 0;
  return status;
}

// Runs one mission and reads its metrics.json.
SweepRun run_one(const PlannedRun& p, const SweepOptions& o, const std::vector<std::string>& keys,
                 const fs::path& out) {
  SweepRun run{.arch = p.arch, .robots = p.robots, .seed = p.seed};
  const fs::path dir =
      out / (to_string(p.arch) + "_r" + std::to_string(p.robots) + "_s" + std::to_string(p.seed));
  run.run_dir = dir.string();
  std::error_code ec;
  fs::remove(dir / "metrics.json", ec);  // a previous sweep's must not pass for this run's
  // no trace.json: a sweep reads metrics.json only
  std::vector<std::string> args = {
      "scancrew",       "run", p.launch, "--out", run.run_dir, "--robots", std::to_string(p.robots),
      "--trace-events", "0"};
  for (const std::string& key : keys) {
    args.emplace_back("--set");
    args.push_back(key + "=" + std::to_string(p.seed));
  }
  for (const std::string& set : o.sets) {
    args.emplace_back("--set");
    args.push_back(set);
  }
  const int status = run_in_child(args);

  const fs::path metrics = dir / "metrics.json";
  if (const auto text = read_text_file(metrics.string())) {
    auto read = read_sweep_metrics(*text, run, metrics.string());
    if (read)
      run = std::move(read).value();
    else
      run.error = read.error();
  } else {
    run.error = metrics.string() + ": not written";
  }
  // 3: the mission ran and wrote its results, out of time or stalled (not a failure here)
  if (status != 0 && status != 3) {
    run.stop_reason = StopReason::kFailed;
    run.error = "scancrew run exited with status " + std::to_string(status) +
                (status == 2    ? " (the launch was refused; see above)"
                 : status > 128 ? " (ended by signal " + std::to_string(status - 128) + ")"
                                : " (see above)");
  } else if (!run.error.empty()) {
    run.stop_reason = StopReason::kFailed;
  }
  return run;
}

std::string describe(const SweepRun& r) {
  char buf[160];
  if (r.stop_reason == StopReason::kFailed) return "failed: " + r.error;
  std::snprintf(buf, sizeof buf, "%s at %.1f s simulated, coverage %.2f %% (%.1f s wall)",
                to_string(r.stop_reason).c_str(),
                r.stop_reason == StopReason::kComplete && std::isfinite(r.completion_time_s)
                    ? r.completion_time_s
                    : r.sim_time_s,
                100 * r.coverage, r.wall_time_s);
  return buf;
}

// Resolves --arch against the sweep or launch file; nullopt (said why) when they do not fit.
std::optional<std::vector<Architecture>> select_architectures(const SweepOptions& o,
                                                              SweepPlan& plan) {
  // the architectures asked, each with its launch file
  std::vector<Architecture> archs;
  for (const std::string& name : o.archs) {
    const auto arch = value_of(kArchitectureNames, name);
    if (!arch) {
      std::fprintf(stderr, "scancrew sweep: --arch: unknown architecture '%s'; allowed: %s\n",
                   name.c_str(), joined_names(kArchitectureNames).c_str());
      return std::nullopt;
    }
    archs.push_back(*arch);
  }
  if (plan.sweep_file) {
    // in kArchitectureNames' order when --arch does not say
    std::vector<std::string> has;
    for (const auto& [arch, name] : kArchitectureNames)
      if (plan.launch_of.count(arch) > 0) {
        if (o.archs.empty()) archs.push_back(arch);
        has.emplace_back(name);
      }
    for (const Architecture a : archs)
      if (plan.launch_of.count(a) == 0) {
        std::fprintf(stderr, "scancrew sweep: %s has no architecture '%s'; it has: %s\n",
                     o.path.c_str(), to_string(a).c_str(), join(has).c_str());
        return std::nullopt;
      }
  } else {
    if (archs.size() != 1) {
      std::fprintf(stderr,
                   "scancrew sweep: %s is a launch file, not a sweep file (no architectures:): "
                   "name its one architecture with --arch (single, centralized or "
                   "distributed)%s\n",
                   o.path.c_str(), archs.empty() ? "" : ", not several");
      return std::nullopt;
    }
    plan.launch_of[archs.front()] = o.path;
  }
  return archs;
}

// Expands the architectures into the planned runs; nullopt (said why) on a bad launch file.
std::optional<std::vector<PlannedRun>> plan_runs(const SweepOptions& o,
                                                 const std::vector<Architecture>& archs,
                                                 SweepPlan& plan) {
  // architecture x robots x seed; "single" is one robot whatever --robots says, a team
  // larger than a launch file lists is skipped for its architecture (said once), and so is
  // a team of one beside a "single" row: it would run the single robot again
  const bool has_single =
      std::find(archs.begin(), archs.end(), Architecture::kSingle) != archs.end();
  std::vector<PlannedRun> runs;
  for (const Architecture arch : archs) {
    const bool single = arch == Architecture::kSingle;
    const std::string& launch = plan.launch_of[arch];
    const TeamSize team = team_size(launch);
    if (team.listed == 0) {
      std::fprintf(stderr, "scancrew sweep: %s: %s is not a launch file\n", to_string(arch).c_str(),
                   launch.c_str());
      return std::nullopt;
    }
    const size_t most = single ? 1 : team.listed;
    const size_t least = !single && has_single ? 2 : 1;
    std::vector<size_t> teams, skipped;
    for (const size_t n : o.robots.empty() ? std::vector<size_t>{team.runs} : o.robots) {
      if (std::find(teams.begin(), teams.end(), n) != teams.end()) continue;
      if (n >= least && n <= most)
        teams.push_back(n);
      else if (std::find(skipped.begin(), skipped.end(), n) == skipped.end())
        skipped.push_back(n);
    }
    if (single && teams.empty()) teams.push_back(1);
    if (!skipped.empty()) {
      std::vector<std::string> names;
      names.reserve(skipped.size());
      for (const size_t n : skipped) names.push_back(std::to_string(n));
      const std::string why = single
                                  ? "1 robot only"
                                  : launch + " lists " + std::to_string(team.listed) + " robots" +
                                        (least > 1 ? "; 1 robot is the single row" : "");
      std::fprintf(stderr, "scancrew sweep: %s: %s (robots %s skipped for it)\n",
                   to_string(arch).c_str(), why.c_str(), join(names, ",").c_str());
    }
    for (const size_t n : teams)
      for (int seed = 1; seed <= o.seeds; ++seed)
        runs.push_back({.arch = arch, .launch = launch, .robots = n, .seed = seed});
  }
  return runs;
}

// Runs the planned runs in order, tables after each, until done or stopped; the runs done.
std::vector<SweepRun> run_all(const std::vector<PlannedRun>& runs, const SweepOptions& o,
                              const std::vector<std::string>& keys, const fs::path& out,
                              const std::string& title, bool& tables_written) {
  g_stop = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::vector<SweepRun> done;
  done.reserve(runs.size());
  tables_written = true;
  for (size_t i = 0; i < runs.size() && g_stop == 0; ++i) {
    const PlannedRun& p = runs[i];
    const std::string head = "[" + std::to_string(i + 1) + "/" + std::to_string(runs.size()) +
                             "] " + to_string(p.arch) + ", " + std::to_string(p.robots) +
                             (p.robots == 1 ? " robot" : " robots") + ", seed " +
                             std::to_string(p.seed);
    std::fprintf(stderr, "%s ...\n", head.c_str());
    std::fflush(stdout);
    done.push_back(run_one(p, o, keys, out));
    std::fflush(stdout);
    std::fprintf(stderr, "%s: %s\n", head.c_str(), describe(done.back()).c_str());
    if (done.back().stop_reason == StopReason::kInterrupted) g_stop = 1;
    // after every run, so that a sweep cut short still leaves its tables
    tables_written = write_file(out / "sweep.csv", format_sweep_csv(done)) &&
                     write_file(out / "sweep.md", format_sweep_markdown(done, title));
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  return done;
}

}  // namespace

int run_sweep(const SweepOptions& o) {
  auto plan = read_plan(o.path);
  if (!plan) {
    std::fprintf(stderr, "scancrew sweep: %s\n", scancrew::log::printable(plan.error()).c_str());
    return 2;
  }
  const auto archs = select_architectures(o, *plan);
  if (!archs) return 2;
  std::vector<std::string> keys(kDefaultSeedKeys.begin(), kDefaultSeedKeys.end());
  if (!o.seed_keys.empty())
    keys = o.seed_keys;
  else if (!plan->seed_keys.empty())
    keys = plan->seed_keys;

  const auto runs = plan_runs(o, *archs, *plan);
  if (!runs) return 2;
  if (runs->empty()) {
    std::fprintf(stderr, "scancrew sweep: nothing to run (no team size fits any launch file)\n");
    return 2;
  }

  const fs::path out =
      o.out_dir.empty() ? fs::path("runs") / ("sweep_" + stem_of(o.path)) : fs::path(o.out_dir);
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "scancrew sweep: cannot create %s: %s\n", out.c_str(),
                 ec.message().c_str());
    return 2;
  }
  std::string title = "Sweep of " + o.path + ": " + std::to_string(o.seeds) +
                      (o.seeds == 1 ? " seed" : " seeds") + " (" + join(keys, ", ") + ")";
  if (!o.sets.empty()) title += "; --set " + join(o.sets, " ");

  bool tables_written = true;
  const std::vector<SweepRun> done = run_all(*runs, o, keys, out, title, tables_written);

  const bool stopped = done.size() < runs->size();
  size_t failed = 0;
  for (const SweepRun& r : done) failed += outcome_of(r) == RunOutcome::kFailed ? 1 : 0;
  std::printf("\n%s", format_sweep_markdown(done, title).c_str());
  std::printf("\n%zu of %zu runs done", done.size(), runs->size());
  if (failed > 0) std::printf(", %zu failed", failed);
  if (stopped) std::printf(" (stopped)");
  std::printf("; tables %s and %s\n", (out / "sweep.md").c_str(), (out / "sweep.csv").c_str());
  return failed > 0 || stopped || !tables_written ? 1 : 0;
}

void add_sweep_command(CLI::App& app, CommandTable& table) {
  auto [sweep, o] = table.add_with_options<SweepOptions>(
      app, "sweep", "run a mission over architectures x robots x seeds; results tables (MD, CSV)",
      run_sweep);
  sweep
      ->add_option("file", o->path,
                   "sweep file (architectures: one launch file each) or a launch file")
      ->required()
      ->check(CLI::ExistingFile);
  sweep
      ->add_option("--robots", o->robots,
                   "team sizes, e.g. 1,2,3,4 (default: every robot of each launch file)")
      ->delimiter(',')
      ->check(CLI::Range(size_t{1}, size_t{1000}));
  sweep->add_option("--arch", o->archs, "architectures (default: every one of the sweep file)")
      ->delimiter(',')
      ->check(CLI::IsMember(name_list(kArchitectureNames)));
  sweep->add_option("--seeds", o->seeds, "runs per team, seeds 1..N")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  sweep->add_option("--out", o->out_dir,
                    "output folder: sweep.md, sweep.csv, a run directory per run "
                    "(default runs/sweep_<file stem>)");
  sweep
      ->add_option("--set", o->sets,
                   "override a parameter in every run: name.key=value (after the seed's)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sweep
      ->add_option("--seed-keys", o->seed_keys,
                   "parameters set to the seed (default: the sweep file's seed_keys, else "
                   "team_simulator.seed,low_level_planner.planner_seed)")
      ->delimiter(',');
}

}  // namespace scancrew::cli
