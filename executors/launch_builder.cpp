// LaunchBuilder's reading of a launch file: the settings (clock, executor, run, security),
// the robots and the component specs, each checked, every error collected.

#include "executors/launch_builder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "executors/registry.hpp"

namespace scancrew {

namespace {

bool is_map_or_absent(const YAML::Node& n) {
  return !n.IsDefined() || n.IsNull() || n.IsMap();
}

}  // namespace

Result<std::unique_ptr<Launch>, Launch::Errors> LaunchBuilder::build(YAML::Node root) {
  if (!root.IsMap())
    return fail(file_ + ": a launch file is a mapping (clock, executor, run, robots, components)");
  apply_overrides(root);
  if (!errors_.empty()) return make_unexpected(errors_);
  auto launch = std::unique_ptr<Launch>(new Launch());
  launch->out_dir_ = out_dir();
  read_settings(root, launch->settings_);
  read_robots(root["robots"], launch->settings_.robots);
  read_components(root["components"]);
  if (!errors_.empty()) return make_unexpected(errors_);
  compose(*launch);
  if (!errors_.empty()) return make_unexpected(errors_);
  return launch;
}

Result<std::unique_ptr<Launch>, Launch::Errors> LaunchBuilder::fail(std::string message) {
  errors_.push_back(std::move(message));
  return make_unexpected(errors_);
}

std::string LaunchBuilder::out_dir() const {
  if (!options_.out_dir.empty()) return options_.out_dir;
  std::string stem = file_.substr(file_.find_last_of('/') + 1);
  stem = stem.substr(0, stem.find('.'));
  return "runs/" + (stem.empty() ? std::string("run") : stem);
}

// --set name.key=value: onto the YAML tree before it is read, so that the value goes
// through the same checks as the file's own.
void LaunchBuilder::apply_overrides(YAML::Node& root) {
  auto errors = apply_launch_overrides(root, options_.overrides, file_);
  errors_.insert(errors_.end(), errors.begin(), errors.end());
}

void LaunchBuilder::merge(const ParamReader& reader) {
  errors_.insert(errors_.end(), reader.errors().begin(), reader.errors().end());
}

void LaunchBuilder::read_settings(const YAML::Node& root, LaunchSettings& s) {
  ParamReader top = make_param_reader(root, file_, "(top level)");
  top.choice("clock", s.clock, kClockTypeNames);
  // the sections below are read on their own; mark them known to the top level
  for (const char* section : {"executor", "run", "robots", "components", "security", "remap"}) {
    if (root[section].IsDefined() && root[section].IsScalar())
      errors_.push_back(yaml_location(file_, root[section]) + ": " + section + ": must be a " +
                        (std::string(section) == "robots" || std::string(section) == "components"
                             ? "list"
                             : "mapping"));
    top_known_.insert(section);
  }
  for (const auto& kv : root)
    if (kv.first.Scalar() != "clock" && !top_known_.count(kv.first.Scalar()))
      errors_.push_back(
          yaml_location(file_, kv.first) + ": " + kv.first.Scalar() +
          ": unknown key; allowed: clock, executor, run, robots, components, security, remap");
  merge(top);
  read_remap_map(root["remap"], "remap", remaps_);

  ParamReader exec = make_param_reader(root["executor"], file_, "executor");
  exec.choice("type", s.executor, kExecutorTypeNames);
  uint64_t threads = 2;
  exec.optional("threads", threads, {1, 64});
  exec.optional("spin_us", s.spin_us, {0, 1e6});
  exec.finish();
  merge(exec);
  s.threads = s.executor == LaunchSettings::ExecutorType::kMultiThreaded ? threads : 1;
  if (s.executor == LaunchSettings::ExecutorType::kStep && s.clock != ClockType::kSim)
    errors_.push_back(yaml_location(file_, root["executor"]) +
                      ": executor.type: 'step' runs on sim time; allowed with clock: sim only");

  ParamReader run = make_param_reader(root["run"], file_, "run");
  run.optional("duration_s", s.duration_s, {0, 1e7});
  run.optional("sim_step_s", s.sim_step_s, {1e-6, 10});
  run.optional("real_time_factor", s.real_time_factor, {0, 1e6});
  run.optional("progress_period_s", s.progress_period_s, {0.01, 3600});
  uint64_t robots = 0;
  run.optional("robots", robots, {0, 1e6});
  s.robots = robots;
  compute_time_.reset();  // unset: decided once the components are known
  const YAML::Node run_node = root["run"];
  if (run_node.IsDefined() && run_node.IsMap() && run_node["compute_time"].IsDefined()) {
    ComputeTime compute_time = ComputeTime::kCharged;
    run.choice("compute_time", compute_time, kComputeTimeNames);
    compute_time_ = compute_time;
  }
  run.optional("compute_scale", s.charge.scale, {1e-3, 1e3});
  uint64_t cores = 2;
  run.optional("place_cores", cores, {1, 1024});
  s.charge.cores = static_cast<int>(cores);
  run.optional("station", s.station);
  run.finish();
  merge(run);

  ParamReader security = make_param_reader(root["security"], file_, "security");
  security.optional("keys", s.security_keys);
  security.finish();
  merge(security);
  if (root["security"].IsDefined() && !root["security"].IsNull() && s.security_keys.empty())
    errors_.push_back(yaml_location(file_, root["security"]) +
                      ": security.keys: the team's key folder (scancrew keys init DIR)");
  if (compute_time_ == ComputeTime::kCharged && s.executor != LaunchSettings::ExecutorType::kStep)
    errors_.push_back(yaml_location(file_, root["run"]) +
                      ": run.compute_time: 'charged' needs executor: {type: step} (sim time); "
                      "on the wall clock compute takes real time anyway");
  if (compute_time_ == ComputeTime::kCharged && options_.process != "run")
    errors_.push_back(yaml_location(file_, root["run"]) +
                      ": run.compute_time: 'charged' is for one process (scancrew run); a team "
                      "split over processes runs with compute free (docs/processes.md)");
}

// The robots: list, or its first N (LaunchOptions::robot_count, else run.robots).
void LaunchBuilder::read_robots(const YAML::Node& node, size_t run_robots) {
  read_robot_list(node);
  const size_t listed = node.IsSequence() ? node.size() : 1;
  const size_t asked = options_.robot_count > 0 ? options_.robot_count : run_robots;
  if (asked > listed)
    errors_.push_back(yaml_location(file_, node) + ": " +
                      (options_.robot_count > 0 ? "robots: " : "run.robots: ") +
                      std::to_string(asked) + " robots asked for" +
                      (options_.robot_count > 0 ? " (--robots)" : "") + ", but the file lists " +
                      std::to_string(listed));
  else if (asked > 0 && robots_.size() > asked)
    robots_.resize(asked);
}

void LaunchBuilder::read_robot_list(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) {
    robots_.push_back({});
    return;
  }
  if (!node.IsSequence() || node.size() == 0) {
    errors_.push_back(yaml_location(file_, node) +
                      ": robots: must be a non-empty list of {id, namespace}");
    return;
  }
  std::set<uint32_t> ids;
  std::set<std::string> names;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string path = "robots[" + std::to_string(i) + "]";
    ParamReader r = make_param_reader(node[i], file_, path);
    RobotSpec robot;
    r.required("id", robot.id, {0, 1e6});
    r.required("namespace", robot.ns);
    r.choice("kind", robot.kind, robot::kRobotKindNames);
    std::vector<double> start;
    r.optional_list("start", start, 4, {-1e5, 1e5});  // x, y, z, yaw_deg
    if (start.size() == 4) {
      robot.start_x_m = start[0];
      robot.start_y_m = start[1];
      robot.start_z_m = start[2];
      robot.start_yaw_rad = start[3] * M_PI / 180.0;
    }
    r.finish();
    merge(r);
    if (!r.ok()) continue;
    if (!valid_name(robot.ns))
      errors_.push_back(yaml_location(file_, node[i]) + ": " + path + ".namespace: '" + robot.ns +
                        "' is not a name; allowed: letters, digits, '_'");
    if (!ids.insert(robot.id).second)
      errors_.push_back(yaml_location(file_, node[i]) + ": " + path +
                        ".id: " + std::to_string(robot.id) + " is used twice");
    if (!names.insert(robot.ns).second)
      errors_.push_back(yaml_location(file_, node[i]) + ": " + path + ".namespace: '" + robot.ns +
                        "' is used twice");
    robots_.push_back(robot);
  }
}

bool LaunchBuilder::valid_name(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

void LaunchBuilder::read_components(const YAML::Node& node) {
  if (!node.IsDefined() || !node.IsSequence() || node.size() == 0) {
    errors_.push_back(yaml_location(file_, node) + ": components: must be a non-empty list");
    return;
  }
  const auto& registry = ComponentRegistry::instance();
  std::map<std::string, size_t> first_with_name;  // a name is one component of the file
  for (size_t i = 0; i < node.size(); ++i) {
    ComponentSpec spec;
    spec.path = "components[" + std::to_string(i) + "]";
    const YAML::Node& c = node[i];
    ParamReader r = make_param_reader(c, file_, spec.path);
    r.required("type", spec.type);
    spec.name = spec.type;  // no name: the type's (one instance of it in the file)
    r.optional("name", spec.name);
    r.optional("per_robot", spec.per_robot);
    read_processes(c, spec, r);
    known_subkeys(
        c, spec.path,
        {"name", "type", "per_robot", "process", "params", "remap", "qos", "callback_group"});
    merge(r);
    if (!r.ok()) continue;
    check_name(c, spec, i, first_with_name);
    if (registry.find(spec.type) == nullptr) {
      std::string known;
      for (const auto& t : registry.types()) known += (known.empty() ? "" : ", ") + t;
      errors_.push_back(yaml_location(file_, c["type"]) + ": " + spec.path +
                        ".type: unknown component '" + spec.type + "'; registered: " + known);
    }
    if (!is_map_or_absent(c["params"]))
      errors_.push_back(yaml_location(file_, c["params"]) + ": " + spec.path +
                        ".params: must be a mapping");
    if (c["params"].IsDefined()) spec.params = c["params"];  // (a missing key is an invalid node)
    read_group(c["callback_group"], spec);
    read_remaps(c["remap"], spec);
    read_qos(c["qos"], spec);
    if (std::find(spec.processes.begin(), spec.processes.end(), options_.process) !=
        spec.processes.end())
      specs_.push_back(std::move(spec));
  }
  if (errors_.empty() && specs_.empty())
    errors_.push_back(file_ + ": no component runs in the '" + options_.process +
                      "' process (components' process: keys)");
}

// A component's name (its type's where it gives none): a name, and one component's only.
void LaunchBuilder::check_name(const YAML::Node& c, const ComponentSpec& spec, size_t index,
                               std::map<std::string, size_t>& first_with_name) {
  const bool named = c["name"].IsDefined();
  const std::string where = yaml_location(file_, named ? c["name"] : c["type"]) + ": " + spec.path +
                            (named ? ".name" : " (no name: its type's)");
  if (!valid_name(spec.name))
    errors_.push_back(where + ": '" + spec.name + "' is not a name; allowed: letters, digits, '_'");
  if (const auto [it, fresh] = first_with_name.emplace(spec.name, index); !fresh)
    errors_.push_back(where + ": '" + spec.name + "' names components[" +
                      std::to_string(it->second) +
                      "] too; each component has a name of its own (two components of one "
                      "type need distinct name: keys)");
}

// process: a command name or a list of them; default [run, robot] (per-robot) or [run].
void LaunchBuilder::read_processes(const YAML::Node& c, ComponentSpec& spec, ParamReader& r) {
  static constexpr std::array<std::string_view, 4> kProcesses = {"run", "sim", "robot", "station"};
  if (!c.IsMap() || !c["process"].IsDefined()) {
    spec.processes = {"run"};
    if (spec.per_robot) spec.processes.emplace_back("robot");
    return;
  }
  const YAML::Node& node = c["process"];
  if (node.IsScalar()) {
    spec.processes = {node.Scalar()};
  } else {
    r.optional_list("process", spec.processes);
  }
  for (const std::string& p : spec.processes)
    if (std::find(kProcesses.begin(), kProcesses.end(), p) == kProcesses.end())
      errors_.push_back(yaml_location(file_, node) + ": " + spec.path + ".process: '" + p +
                        "' is no process; allowed: run, sim, robot, station (or a list)");
  if (spec.processes.empty())
    errors_.push_back(yaml_location(file_, node) + ": " + spec.path +
                      ".process: an empty list; allowed: run, sim, robot, station");
}

void LaunchBuilder::known_subkeys(const YAML::Node& c, const std::string& path,
                                  std::initializer_list<std::string_view> allowed) {
  if (!c.IsMap()) return;
  for (const auto& kv : c) {
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string list;
    for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    errors_.push_back(yaml_location(file_, kv.first) + ": " + path + "." + key +
                      ": unknown key; allowed: " + list);
  }
}

void LaunchBuilder::read_group(const YAML::Node& node, ComponentSpec& spec) {
  if (!node.IsDefined() || node.IsNull()) return;
  ParamReader r = make_param_reader(node, file_, spec.path + ".callback_group");
  r.required("name", spec.group_name);
  r.choice("type", spec.group_type, kCallbackGroupTypeNames);
  r.finish();
  merge(r);
}

void LaunchBuilder::read_remaps(const YAML::Node& node, ComponentSpec& spec) {
  read_remap_map(node, spec.path + ".remap", spec.remaps);
}

void LaunchBuilder::read_remap_map(const YAML::Node& node, const std::string& path,
                                   std::map<std::string, std::string>& out) {
  if (!node.IsDefined() || node.IsNull()) return;
  if (!node.IsMap()) {
    errors_.push_back(yaml_location(file_, node) + ": " + path + ": must be a mapping port: topic");
    return;
  }
  for (const auto& kv : node) {
    const std::string port = kv.first.Scalar();
    if (!kv.second.IsScalar() || kv.second.Scalar().empty() || kv.second.Scalar() == "/") {
      errors_.push_back(
          yaml_location(file_, kv.first) + ": " + path + "." + port +
          ": remap to nothing; allowed: a topic name, relative (ns/name) or absolute (/name)");
      continue;
    }
    out[port] = kv.second.Scalar();
  }
}

void LaunchBuilder::read_qos(const YAML::Node& node, ComponentSpec& spec) {
  if (!node.IsDefined() || node.IsNull()) return;
  if (!node.IsMap()) {
    errors_.push_back(yaml_location(file_, node) + ": " + spec.path +
                      ".qos: must be a mapping port: {pool_size, depth, history}");
    return;
  }
  for (const auto& kv : node) {
    const std::string port = kv.first.Scalar();
    ParamReader r = make_param_reader(kv.second, file_, spec.path + ".qos." + port);
    PortQos q;
    uint64_t pool = 0, depth = 0;
    r.optional("pool_size", pool, {1, 1e6});
    r.optional("depth", depth, {1, 1e6});
    if (kv.second.IsMap() && kv.second["history"].IsDefined()) {
      History history = History::kKeepLast;
      r.choice("history", history, kHistoryNames);
      q.history = history;
    }
    r.finish();
    merge(r);
    if (pool) q.pool_size = pool;
    if (depth) q.depth = depth;
    spec.qos[port] = q;
  }
}

}  // namespace scancrew
