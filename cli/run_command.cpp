#include "cli/run_command.hpp"

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "cli/commands.hpp"
#include "cli/mission_compose.hpp"
#include "cli/report.hpp"
#include "cli/run_directory.hpp"
#include "cli/run_record.hpp"
#include "components/dds_bridge/dds_bridge.hpp"
#include "components/mission_monitor/mission_monitor.hpp"
#include "executors/launch.hpp"
#include "executors/log.hpp"

namespace scancrew::cli {

namespace {

namespace fs = std::filesystem;
using mission_monitor::MissionMonitor;

Launch* g_running = nullptr;

volatile std::sig_atomic_t g_interrupted = 0;

void on_signal(int /*signal*/) {
  g_interrupted = 1;
  if (g_running != nullptr) g_running->request_stop();
}

std::string local_time_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", &tm);
  return buf;
}

void print_mission_progress(const MissionMonitor& monitor, double elapsed_s, double duration_s,
                            double wall_s, bool final) {
  static const bool tty = isatty(fileno(stderr)) != 0;
  char head[96];
  std::snprintf(head, sizeof head, "t %6.1f / %.0f s  x%.1f  ", elapsed_s, duration_s,
                wall_s > 0 ? elapsed_s / wall_s : 0.0);
  std::fprintf(stderr, "%s%s%s%s", tty ? "\r\033[K" : "", head, monitor.status_line().c_str(),
               tty && !final ? "" : "\n");
  std::fflush(stderr);
}

// What a bridge sent and received: the data exchanged (thesis 5.4), per minute of sim time.
void print_bridge_bytes(const dds_bridge::DdsBridge& bridge, double sim_s) {
  const dds_bridge::BridgeStats s = bridge.stats();
  uint64_t sent = 0, received = 0, samples = 0;
  for (const auto& t : s.topics) {
    sent += t.sent_bytes;
    received += t.received_bytes;
    samples += t.sent_samples;
  }
  const double minutes = sim_s / 60.0;
  std::printf(
      "dds %s (bridge %u): sent %llu bytes in %llu samples (%.0f bytes per minute of sim "
      "time), received %llu bytes; peers lost %llu\n",
      bridge.qualified_name().c_str(), bridge.bridge_id(), static_cast<unsigned long long>(sent),
      static_cast<unsigned long long>(samples),
      minutes > 0 ? static_cast<double>(sent) / minutes : 0.0,
      static_cast<unsigned long long>(received), static_cast<unsigned long long>(s.peers_lost));
}

// Whether the launch may start: a mission whose robot or station has an input nothing feeds
// would run blind (a mapper reading a depth topic nobody publishes completed at once), and
// is refused as a bad launch file is (`strict`). The world's components (the monitor, a
// replay) only watch: a warning for them. One process of a team split over processes gets
// its other inputs over DDS: not checked. Prints the graph's warnings.
bool inputs_connected(Launch& launch, bool strict, const std::string& launch_path) {
  const GraphReport graph_report = launch.report();
  std::vector<std::string> unconnected;
  for (const EndpointInfo& e : graph_report.unconnected_inputs)
    if (strict && !launch.is_world(e.component))
      unconnected.push_back("unconnected input: " + e.component + "." + e.port + " reads '" +
                            e.topic + "' (" + e.type_name + ") but nothing publishes it");
  for (const auto& w : graph_report.warnings)
    if (std::find(unconnected.begin(), unconnected.end(), w) == unconnected.end())
      std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (unconnected.empty()) return true;
  std::fprintf(stderr,
               "scancrew: %s: %zu error(s): a mission's components must have every input "
               "connected; nothing was started\n",
               launch_path.c_str(), unconnected.size());
  for (const auto& e : unconnected)
    std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
  return false;
}

// The launch's bridges; one process of a team: its bridge's lockstep paces the steps
// (docs/processes.md). Nothing when a lockstep bridge runs on the wall clock (said why).
std::optional<std::vector<const dds_bridge::DdsBridge*>> gate_on_bridges(
    Launch& launch, const std::string& launch_path) {
  std::vector<const dds_bridge::DdsBridge*> bridges;
  for (const auto& c : launch.components())
    if (auto* bridge = dynamic_cast<dds_bridge::DdsBridge*>(c.get())) {
      bridges.push_back(bridge);
      if (StepGate* gate = bridge->step_gate()) {
        if (launch.settings().executor != LaunchSettings::ExecutorType::kStep) {
          std::fprintf(stderr,
                       "scancrew: %s: %s: lockstep needs executor: {type: step} (sim time)\n",
                       launch_path.c_str(), bridge->qualified_name().c_str());
          return std::nullopt;
        }
        launch.set_step_gate(gate);
      }
    }
  return bridges;
}

// Runs the launch to its end, Ctrl-C or SIGTERM, printing progress; fills run's times.
// Whether a signal stopped it (not the monitor).
bool run_until_stopped(Launch& launch, const MissionMonitor* monitor, RunFacts& run) {
  g_running = &launch;
  g_interrupted = 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::fprintf(stderr, "scancrew: running %s (%zu components; Ctrl-C stops%s)\n",
               run.launch_path.c_str(), launch.components().size(),
               monitor ? ", results are still written" : "");
  const auto wall_start = std::chrono::steady_clock::now();
  const auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  // the last progress line comes before the components' closing reports
  run.sim_s = launch.run([&](double elapsed, double duration, bool final) {
    if (monitor)
      print_mission_progress(*monitor, elapsed, duration, wall(), final);
    else
      print_progress(stderr, launch.graph(), elapsed, duration, final);
  });
  run.wall_s = wall();
  const bool interrupted = g_interrupted != 0;  // Ctrl-C / SIGTERM, not the monitor's stop
  g_running = nullptr;
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  return interrupted;
}

// What the components reported failed during the run (Component::report_failure), listed;
// false when nothing did.
bool print_failures(Launch& launch) {
  const auto failures = launch.graph().failures();
  if (failures.empty()) return false;
  std::fprintf(stderr, "scancrew run: %zu failure(s) during the run lost data or output:\n",
               failures.size());
  for (const auto& f : failures)
    std::fprintf(stderr, "  %s\n", scancrew::log::printable(f).c_str());
  return true;
}

// The stop reason of a monitor that finished ("complete", "stalled"); a reason the table does
// not name (a monitor that learned a new one) is said and recorded as stalled: not complete.
StopReason stop_reason_of(const MissionMonitor& monitor) {
  const std::string name = monitor.stop_reason();
  if (const auto reason = value_of(kStopReasonNames, name)) return *reason;
  std::fprintf(stderr,
               "scancrew run: the mission monitor stopped for '%s', which no stop reason names "
               "(%s); recorded as stalled\n",
               name.c_str(), joined_names(kStopReasonNames).c_str());
  return StopReason::kStalled;
}

// The end of a mission: its run directory, and the exit status (docs/missions.md, "Exit
// status").
int finish_mission(Launch& launch, MissionMonitor& monitor, RunFacts& run, bool interrupted,
                   const fs::path& out) {
  monitor.close_time_breakdown();
  run.stop_reason = monitor.finished() ? stop_reason_of(monitor)
                    : interrupted      ? StopReason::kInterrupted
                                       : StopReason::kTimeBudget;
  // the per-topic table goes to the run directory; the terminal gets the summary
  if (std::FILE* f = std::fopen((out / "topics.txt").c_str(), "w"); f != nullptr) {
    print_topic_stats(f, launch.graph(), run.sim_s);
    std::fclose(f);
  }
  if (!write_run_directory(launch, monitor, run, out)) return 1;
  // a robot whose depth never reached a map saw nothing: the graph is miswired
  if (const auto blind = monitor.robots_without_depth(); !blind.empty()) {
    std::string names;
    for (const auto& n : blind) names += (names.empty() ? "" : ", ") + n;
    std::fprintf(stderr,
                 "scancrew run: %s: configuration error: no map integrated a depth image of %s "
                 "(is the mapper's depth_topic published for that robot? scancrew graph %s)\n",
                 run.launch_path.c_str(), names.c_str(), run.launch_path.c_str());
    return 2;
  }
  // docs/missions.md, "Exit status"
  if (print_failures(launch)) return 4;
  if (run.stop_reason == StopReason::kComplete) return 0;
  return interrupted ? 130 : 3;
}

// The launch file's text with a foxglove_bridge (the live view) appended to its components,
// run in `process`: the file re-emitted, so its comments go.
Result<std::string, std::string> with_live_view(const std::string& text, const std::string& path,
                                                int port, const std::string& process) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return make_unexpected(path + ": " + e.what());
  }
  if (!root.IsMap() || !root["components"].IsSequence())
    return make_unexpected(path + ": --live: the launch file has no components: list");
  YAML::Node bridge;
  bridge["name"] = "foxglove_bridge";
  bridge["type"] = "foxglove_bridge";
  bridge["per_robot"] = false;
  bridge["process"].push_back(process);
  bridge["params"]["port"] = port;
  root["components"].push_back(bridge);
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str());
}

}  // namespace

std::unique_ptr<Launch> compose_or_report(const std::string& path, const LaunchOptions& options,
                                          size_t robot_count, int live_port) {
  auto text = launch_file_text(path, robot_count);
  if (text && live_port >= 0) text = with_live_view(*text, path, live_port, options.process);
  if (!text) {
    std::fprintf(stderr, "scancrew: %s; nothing was started\n",
                 scancrew::log::printable(text.error()).c_str());
    return nullptr;
  }
  auto composed = Launch::from_string(*text, path, options);
  if (!composed) {
    std::fprintf(stderr, "scancrew: %s: %zu error(s); nothing was started\n", path.c_str(),
                 composed.error().size());
    for (const auto& e : composed.error())
      std::fprintf(stderr, "  %s\n", scancrew::log::printable(e).c_str());
    return nullptr;
  }
  return std::move(composed).value();
}

int run_launch(const RunOptions& o) {
  auto launch = compose_or_report(o.launch_path,
                                  {.overrides = o.sets,
                                   .out_dir = o.out_dir,
                                   .robot_count = o.robot_count,
                                   .process = o.process,
                                   .robot_id = o.robot_id},
                                  o.robot_count, o.live_port);
  if (!launch) return 2;
  MissionMonitor* monitor = launch->find_component<MissionMonitor>();
  if (!inputs_connected(*launch, monitor != nullptr && o.process == "run", o.launch_path)) return 2;
  const fs::path out = launch->out_dir();
  if (monitor != nullptr) {
    // one process of a split team sees no maps of the others: it cannot tell
    monitor->set_depth_required(o.process == "run");
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) {
      std::fprintf(stderr, "scancrew run: cannot create the run directory %s: %s\n", out.c_str(),
                   ec.message().c_str());
      return 1;
    }
    if (!write_run_record(out, o)) return 1;  // launch.resolved.yaml, run.json
    launch->set_stop_condition([monitor] { return monitor->finished(); });
    if (o.trace_events > 0) launch->enable_tracing(o.trace_events);
  }
  const auto bridges = gate_on_bridges(*launch, o.launch_path);
  if (!bridges) return 2;
  RunFacts run{.launch_path = o.launch_path,
               .started = local_time_now(),
               .started_at = fs::file_time_type::clock::now()};
  const bool interrupted = run_until_stopped(*launch, monitor, run);
  for (const auto* bridge : *bridges) print_bridge_bytes(*bridge, run.sim_s);
  if (monitor == nullptr) {
    print_topic_stats(stdout, launch->graph(), run.sim_s);
    return print_failures(*launch) ? 4 : 0;  // docs/missions.md, "Exit status"
  }
  return finish_mission(*launch, *monitor, run, interrupted, out);
}

namespace {

// The options of a command that runs a launch file (run, and the parts of a split team).
void add_launch_options(CLI::App* cmd, RunOptions& o, const char* out_help,
                        const char* robots_help) {
  cmd->add_option("launch", o.launch_path, "launch file (YAML)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", o.out_dir, out_help);
  cmd->add_option("--set", o.sets,
                  "override a parameter: name.key=value (a component's name, or run / executor); "
                  "clock=wall: run on the wall clock, multi-threaded (docs/missions.md)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  cmd->add_option("--robots", o.robot_count, robots_help)
      ->check(CLI::Range(size_t{1}, size_t{1000}));
  cmd->add_option("--trace-events", o.trace_events,
                  "missions: callbacks kept for trace.json (24 bytes each; 0: no tracing)")
      ->capture_default_str();
  cmd->add_option("--live", o.live_port,
                  "live view in Foxglove: serve the topics on ws://localhost:PORT (default 8765; "
                  "0: any free port; give it after the launch file; docs/visualization.md)")
      ->expected(0, 1)
      ->default_str("8765")
      ->check(CLI::Range(0, 65535));
}

}  // namespace

void add_run_commands(CLI::App& app, CommandTable& table) {
  auto [run, run_options] = table.add_with_options<RunOptions>(
      app, "run", "compose a launch file and run it; a mission writes its run directory and report",
      run_launch);
  add_launch_options(
      run, *run_options, "run directory ({out} in the launch file; default runs/<launch stem>)",
      "run the first N robots of the launch file's robots: list (default: all); a mission "
      "file is composed with N robots");

  // one process of a team split over processes (docs/processes.md)
  const auto add_part = [&](const char* name, const char* what) {
    auto options = std::make_shared<RunOptions>();
    options->process = name;
    CLI::App* cmd = app.add_subcommand(name, what);
    add_launch_options(
        cmd, *options, "run directory, the same for every process of the team ({out})",
        "the team: the first N robots of the launch file (the same in every process)");
    table.add(cmd, [options] { return run_launch(*options); });
    return std::pair{cmd, options.get()};
  };
  add_part("sim", "the team simulator's process of a team split over processes (lockstep leader)");
  auto [robot, robot_options] =
      add_part("robot", "one robot's process of a team split over processes");
  robot->add_option("--robot", robot_options->robot_id, "this process's robot id")->required();
  add_part("station", "the ground station's process of a centralized team split over processes");
}

}  // namespace scancrew::cli
