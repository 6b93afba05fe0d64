#include "executors/launch.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <set>
#include <thread>

#include "executors/launch_builder.hpp"
#include "executors/params_impl.hpp"

namespace scancrew {

namespace {

// The run: keys that mean sim time: the wall clock drops them from the file and refuses them
// from --set.
constexpr const char* kSimTimeRunKeys[] = {"compute_time", "real_time_factor", "sim_step_s"};

// --set clock=wall: the launch runs on the wall clock as on robots. A step executor becomes
// multi_threaded with a thread per core (a file's single_threaded or multi_threaded is kept);
// the sim-time run: keys are dropped. `set` holds the section.key names --set gave: one that
// asks for sim time contradicts the wall clock and is refused.
void switch_to_wall_clock(YAML::Node& root, const std::set<std::string>& set,
                          std::vector<std::string>& errors) {
  const auto refuse = [&](const std::string& key, const char* why) {
    errors.push_back("--set clock=wall contradicts --set " + key + ": " + why);
  };
  const YAML::Node type = root["executor"].IsMap() ? root["executor"]["type"] : YAML::Node();
  const bool step = !type.IsDefined() || (type.IsScalar() && type.Scalar() == "step");
  if (set.count("executor.type") && step)
    refuse("executor.type", "the step executor runs on sim time");
  for (const char* key : kSimTimeRunKeys)
    if (set.count(std::string("run.") + key))
      refuse(std::string("run.") + key,
             "it is a sim-time setting (on the wall clock compute takes real time, at real-time "
             "factor 1)");
  root["clock"] = "wall";
  if (step) {
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    YAML::Node executor(YAML::NodeType::Map);
    executor["type"] = "multi_threaded";
    executor["threads"] = std::min(cores, 64u);
    root["executor"] = executor;
  }
  if (root["run"].IsMap())
    for (const char* key : kSimTimeRunKeys) root["run"].remove(key);
}

}  // namespace

std::vector<std::string> apply_launch_overrides(YAML::Node& root,
                                                const std::vector<std::string>& overrides,
                                                const std::string& file) {
  std::vector<std::string> errors;
  std::set<std::string> set;  // section.key of run / executor / security
  std::optional<std::string> clock;
  for (const std::string& o : overrides) {
    const auto eq = o.find('=');
    const auto dot = o.find('.');
    if (o.starts_with("clock=")) {
      clock = o.substr(eq + 1);
      if (*clock != "wall" && *clock != "sim")
        errors.push_back("--set " + o + ": clock is 'wall' or 'sim'");
      continue;
    }
    if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 ||
        dot + 1 == eq) {
      errors.push_back("--set " + o + ": expected name.key=value (a component's name or " +
                       "run / executor / security, then the parameter), or clock=wall|sim");
      continue;
    }
    const std::string name = o.substr(0, dot), key = o.substr(dot + 1, eq - dot - 1);
    YAML::Node value;
    try {
      value = YAML::Load(o.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      errors.push_back("--set " + o + ": the value is not YAML: " + e.msg);
      continue;
    }
    if (name == "run" || name == "executor" || name == "security") {
      if (!root[name].IsDefined() || root[name].IsNull())
        root[name] = YAML::Node(YAML::NodeType::Map);
      root[name][key] = value;
      set.insert(name + "." + key);
      continue;
    }
    bool found = false;
    YAML::Node components = root["components"];
    if (components.IsSequence())
      for (size_t i = 0; i < components.size(); ++i) {
        YAML::Node c = components[i];
        // a component without a name: is named by its type
        const YAML::Node named = c.IsMap() && c["name"].IsDefined() ? c["name"] : c["type"];
        if (!c.IsMap() || !named.IsScalar() || named.Scalar() != name) continue;
        if (!c["params"].IsDefined() || c["params"].IsNull())
          c["params"] = YAML::Node(YAML::NodeType::Map);
        c["params"][key] = value;
        found = true;
      }
    if (!found)
      errors.push_back("--set " + o + ": no component named '" + name +
                       "' (nor run / executor / security) in " + file);
  }
  if (clock == "wall") switch_to_wall_clock(root, set, errors);
  if (clock == "sim") root["clock"] = "sim";
  return errors;
}

Result<std::unique_ptr<Launch>, Launch::Errors> Launch::from_string(const std::string& text,
                                                                    const std::string& label,
                                                                    const LaunchOptions& options) {
  LaunchBuilder builder(label, options);
  auto root = parse_yaml(text, label);
  if (!root) return builder.fail(root.error());
  return builder.build(*root);
}

Result<std::unique_ptr<Launch>, Launch::Errors> Launch::from_file(const std::string& path,
                                                                  const LaunchOptions& options) {
  const auto text = read_text_file(path);
  if (!text)
    return make_unexpected(Errors{path + ": cannot read the launch file: " + text.error()});
  return from_string(*text, path, options);
}

Launch::~Launch() {
  deactivate_all();
  for (auto& c : components_) {
    for (Executable* e : c->executables()) {
      if (executor_) executor_->remove(*e);
      if (step_executor_) step_executor_->remove(*e);
    }
    (void)c->shutdown();
  }
  // components (and their endpoints) go before the graph that owns the topics
  components_.clear();
}

void Launch::enable_tracing(size_t max_events) {
  auto tracer = std::make_unique<Tracer>(max_events);
  if (executor_) executor_->set_tracer(tracer.get());
  if (step_executor_) step_executor_->set_tracer(tracer.get());
  tracer_ = std::move(tracer);
}

void Launch::activate_all() {
  for (auto& c : components_)
    if (c->state() == LifecycleState::kInactive) (void)c->activate();
}

void Launch::deactivate_all() {
  for (auto& c : components_)
    if (c->state() == LifecycleState::kActive) (void)c->deactivate();
}

double Launch::run(const Progress& progress) {
  stop_requested_.store(false);
  activate_all();
  const double ran = step_executor_ ? run_stepped(progress) : run_threaded(progress);
  if (progress) progress(ran, settings_.duration_s, true);
  deactivate_all();
  // after the components wrote what they write on deactivation (meshes, maps)
  if (step_executor_ && step_gate_ != nullptr) step_gate_->finish(step_executor_->clock().now_ns());
  return ran;
}

double Launch::run_stepped(const Progress& progress) {
  const auto step_ns = static_cast<int64_t>(settings_.sim_step_s * 1e9);
  const auto end_ns = static_cast<int64_t>(settings_.duration_s * 1e9);
  const auto period_ns = static_cast<int64_t>(settings_.progress_period_s * 1e9);
  SimClock& clock = step_executor_->clock();
  const int64_t start = clock.now_ns();
  int64_t next_report = start + period_ns;
  while (!stop_requested_.load() && (end_ns == 0 || clock.now_ns() - start < end_ns) &&
         !(stop_when_ && stop_when_())) {
    int64_t target = clock.now_ns() + step_ns;
    if (end_ns != 0) target = std::min(target, start + end_ns);
    if (step_gate_ != nullptr) {
      const auto gated = step_gate_->before_step(target);
      if (!gated) break;
      // a process that starts behind its team (a restarted robot following a running
      // simulator) jumps to the team's time: each timer fires once, not once per period it
      // did not live through
      if (clock.now_ns() == start && *gated > target) clock.advance_to(*gated);
      target = std::max(*gated, clock.now_ns());
    }
    step_executor_->run_until(target);
    if (step_gate_ != nullptr) step_gate_->after_step(clock.now_ns());
    if (progress && clock.now_ns() >= next_report) {
      progress(static_cast<double>(clock.now_ns() - start) * 1e-9, settings_.duration_s, false);
      next_report += period_ns;
    }
  }
  return static_cast<double>(clock.now_ns() - start) * 1e-9;
}

double Launch::run_threaded(const Progress& progress) {
  std::thread spinner([this] { executor_->spin(); });
  const auto wall_start = std::chrono::steady_clock::now();
  const auto elapsed_wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  };
  auto* sim = settings_.clock == ClockType::kSim ? static_cast<SimClock*>(clock_.get()) : nullptr;
  const int64_t sim_start = sim ? sim->now_ns() : 0;
  const auto elapsed = [&] {
    return sim ? static_cast<double>(sim->now_ns() - sim_start) * 1e-9 : elapsed_wall();
  };
  double next_report = settings_.progress_period_s;
  while (!stop_requested_.load() &&
         (settings_.duration_s == 0 || elapsed() < settings_.duration_s) &&
         !(stop_when_ && stop_when_())) {
    if (sim) {
      // free-running sim time, paced to the real-time factor (0: as fast as possible)
      const int64_t step_ns = static_cast<int64_t>(settings_.sim_step_s * 1e9);
      sim->advance_to(sim->now_ns() + step_ns);
      if (settings_.real_time_factor > 0) {
        const double due_wall = elapsed() / settings_.real_time_factor;
        const double ahead = due_wall - elapsed_wall();
        if (ahead > 0) std::this_thread::sleep_for(std::chrono::duration<double>(ahead));
      }
    } else {
      // wall time: the executor threads do the work; this thread only watches the clock
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (progress && elapsed() >= next_report) {
      progress(elapsed(), settings_.duration_s, false);
      next_report += settings_.progress_period_s;
    }
  }
  executor_->stop();
  spinner.join();
  return elapsed();
}

}  // namespace scancrew
