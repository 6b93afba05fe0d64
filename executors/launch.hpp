#pragma once

// Launch: composes one process from a YAML launch file (launch_cfg/*.yaml) — the
// clock, the executor, the robots and their namespaces, the component instances with
// their parameters, remaps, QoS and callback groups — and runs it.
//
// Composition is all-or-nothing: every error of the file (unknown component, missing,
// mistyped or out-of-range parameter, unknown key, topic type mismatch, remap to
// nothing or to an unknown port) is collected with file, line and key, and if there is
// any, nothing is started. See docs/launch_files.md for the format.
//
// Thread safety: build and run from one thread; request_stop() from any thread or a
// signal handler.

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "executors/component.hpp"
#include "executors/executor.hpp"
#include "executors/graph.hpp"
#include "executors/step_executor.hpp"
#include "executors/trace.hpp"

namespace scancrew {

struct LaunchSettings {
  enum class ExecutorType { kSingleThreaded, kMultiThreaded, kStep };
  ClockType clock = ClockType::kWall;
  ExecutorType executor = ExecutorType::kSingleThreaded;
  size_t threads = 1;
  double spin_us = 0.0;            // threaded executors: bounded spin before blocking
  double duration_s = 0.0;         // 0: until request_stop()
  double sim_step_s = 0.01;        // sim clock: time advanced per step
  double real_time_factor = 0.0;   // sim clock, threaded executor: 0 = as fast as possible
  double progress_period_s = 1.0;  // how often run() reports progress
  size_t robots = 0;  // run.robots: the first N robots of the robots: list run (0: all)
  // step executor: whether callbacks take sim time (StepExecutor). run.compute_time:
  // charged | free; unset: charged for a mission (a launch with a mission_monitor) run in one
  // process, free otherwise. run.compute_scale, run.place_cores: the computers modelled.
  ComputeTime compute_time = ComputeTime::kFree;
  ComputeCharge charge;
  // run.station: whether the components that are not per robot run on a ground station's
  // computer (a place of their own); false: on the one robot's (a single-robot mission,
  // everything on board). Only a launch with one robot may say false.
  bool station = true;
  // security.keys: the team's key folder (scancrew keys init / add; docs/security.md); the
  // DDS bridges then run authenticated and encrypted, each as its place. Empty: plain DDS.
  std::string security_keys;
};

// executor.type
inline constexpr EnumNames<LaunchSettings::ExecutorType, 3> kExecutorTypeNames = {
    {{LaunchSettings::ExecutorType::kSingleThreaded, "single_threaded"},
     {LaunchSettings::ExecutorType::kMultiThreaded, "multi_threaded"},
     {LaunchSettings::ExecutorType::kStep, "step"}}};

// What the command line adds to a launch file.
struct LaunchOptions {
  // "name.key=value": sets params.key of the component `name`, or key of the run / executor
  // section ("run.duration_s=60"); the value is YAML ("[1, 2]", "true", "0.2").
  std::vector<std::string> overrides;
  // Replaces "{out}" in every component's string parameters (the run directory); empty:
  // "runs/<launch file stem>".
  std::string out_dir;
  // N: the first N robots of the file's robots: list (more than it lists: an error); 0: as
  // the file says (run.robots, else all of them).
  size_t robot_count = 0;
  // Which process of a team this launch composes (docs/processes.md): "run" (everything in
  // one process, `scancrew run`), "sim", "robot" or "station". A component runs in the
  // commands its `process:` key lists (default: [run, robot] for per-robot components,
  // [run] for the others).
  std::string process = "run";
  // process "robot": the robot (id) this process is; its per-robot components are made for
  // it alone, while every component still sees the whole team (team()).
  uint32_t robot_id = 0;
};

// What a step-executed launch asks before and tells after each step: the lockstep of a
// team split over processes (a simulator leading, robots following). Methods run on the
// thread that calls Launch::run.
class StepGate {
 public:
  virtual ~StepGate() = default;
  // Before stepping the clock to target_ns (may block). Returns the time to step to (at
  // least the clock's now), or nullopt to end the run.
  virtual std::optional<int64_t> before_step(int64_t target_ns) = 0;
  // After the step, with the clock at now_ns.
  virtual void after_step(int64_t now_ns) = 0;
  // Once, when the run ends for any reason, after the components' deactivation, with the
  // clock at now_ns.
  virtual void finish(int64_t now_ns) = 0;
  // Ends a blocked before_step soon (async-signal-safe: Launch::request_stop calls it).
  void cancel() { cancelled_.store(true); }

 protected:
  bool cancelled() const { return cancelled_.load(); }

 private:
  std::atomic<bool> cancelled_{false};
};

class Launch {
 public:
  using Errors = std::vector<std::string>;
  // Called every progress period and once at the end (final: true, before the components
  // are deactivated and report): elapsed and total (0 = open-ended) seconds on the launch's
  // clock.
  using Progress = std::function<void(double elapsed_s, double duration_s, bool final)>;

  static Result<std::unique_ptr<Launch>, Errors> from_file(const std::string& path,
                                                           const LaunchOptions& options = {});
  static Result<std::unique_ptr<Launch>, Errors> from_string(const std::string& text,
                                                             const std::string& label,
                                                             const LaunchOptions& options = {});
  // The run directory "{out}" stands for.
  const std::string& out_dir() const { return out_dir_; }
  ~Launch();
  Launch(const Launch&) = delete;
  Launch& operator=(const Launch&) = delete;

  const LaunchSettings& settings() const { return settings_; }
  Graph& graph() { return *graph_; }
  const std::vector<std::unique_ptr<Component>>& components() const { return components_; }
  GraphReport report() const { return graph_->check(); }
  // What the components say about the run (Component::summarize), in launch order.
  RunSummary summary() const {
    RunSummary s;
    for (const auto& c : components_) c->summarize(s);
    return s;
  }

  // Activates every component, runs for settings().duration_s (or until request_stop()),
  // then deactivates them. Returns the seconds run on the launch's clock.
  double run(const Progress& progress = {});
  // The first component of type T (null if none), to read its counters after a run.
  template <class T>
  T* find_component() const {
    for (const auto& c : components_)
      if (auto* t = dynamic_cast<T*>(c.get())) return t;
    return nullptr;
  }
  void request_stop() {
    stop_requested_.store(true);
    if (step_gate_ != nullptr) step_gate_->cancel();
  }
  // Checked between steps (step executor) or progress polls (threaded): true ends run() as
  // request_stop() does. Set before run(), from the thread that runs it.
  void set_stop_condition(std::function<bool()> stop_when) { stop_when_ = std::move(stop_when); }
  // Step executor only: a gate consulted around every step (StepGate); null: none. The gate
  // must outlive run().
  void set_step_gate(StepGate* gate) { step_gate_ = gate; }

  // Records every callback of the launch's executor from now on (docs/runtime.md,
  // "Tracing"): totals per component, and up to max_events timeline events (buffer
  // allocated here). Call before run(), not while it runs. Off by default.
  void enable_tracing(size_t max_events);
  // The tracer (null while tracing is off), for component_times() and write_chrome_trace().
  const Tracer* tracer() const { return tracer_.get(); }
  // Whether the component (its qualified name) is the world's (the simulator, the mission's
  // instruments: ComponentRegistry::Entry::world), not a robot's or the station's.
  bool is_world(const std::string& qualified_name) const {
    return world_components_.count(qualified_name) > 0;
  }
  // Step executor, compute charged: what each place (robot, station) computed; else empty.
  std::vector<PlaceStats> place_stats() const {
    return step_executor_ ? step_executor_->place_stats() : std::vector<PlaceStats>{};
  }

 private:
  Launch() = default;
  double run_threaded(const Progress& progress);
  double run_stepped(const Progress& progress);
  void activate_all();
  void deactivate_all();

  LaunchSettings settings_;
  std::shared_ptr<Clock> clock_;
  std::unique_ptr<Graph> graph_;
  std::vector<std::shared_ptr<CallbackGroup>> groups_;
  std::vector<std::unique_ptr<Component>> components_;
  std::unique_ptr<Executor> executor_;
  std::unique_ptr<StepExecutor> step_executor_;
  std::atomic<bool> stop_requested_{false};
  std::function<bool()> stop_when_;
  StepGate* step_gate_ = nullptr;
  std::string out_dir_;
  std::unique_ptr<Tracer> tracer_;          // the executor points to it; null: tracing off
  std::set<std::string> world_components_;  // qualified names

  friend class LaunchBuilder;
};

}  // namespace scancrew
