#include "executors/launch.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "executors/params_impl.hpp"
#include "executors/registry.hpp"

namespace scancrew {

std::vector<std::string> apply_launch_overrides(YAML::Node& root,
                                                const std::vector<std::string>& overrides,
                                                const std::string& file) {
  std::vector<std::string> errors;
  for (const std::string& o : overrides) {
    const auto eq = o.find('=');
    const auto dot = o.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 ||
        dot + 1 == eq) {
      errors.push_back("--set " + o + ": expected name.key=value (a component's name or " +
                       "run / executor / security, then the parameter)");
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
      continue;
    }
    bool found = false;
    YAML::Node components = root["components"];
    if (components.IsSequence())
      for (size_t i = 0; i < components.size(); ++i) {
        YAML::Node c = components[i];
        if (!c.IsMap() || !c["name"].IsScalar() || c["name"].Scalar() != name) continue;
        if (!c["params"].IsDefined() || c["params"].IsNull())
          c["params"] = YAML::Node(YAML::NodeType::Map);
        c["params"][key] = value;
        found = true;
      }
    if (!found)
      errors.push_back("--set " + o + ": no component named '" + name +
                       "' (nor run / executor / security) in " + file);
  }
  return errors;
}

namespace {

using RobotSpec = TeamMember;

struct ComponentSpec {
  std::string name, type;
  bool per_robot = true;
  std::vector<std::string> processes;  // the commands that compose it (LaunchOptions::process)
  std::string group_name;              // empty: a group of its own
  CallbackGroup::Type group_type = CallbackGroup::Type::kMutuallyExclusive;
  YAML::Node params;
  std::string path;  // "components[i]"
  std::map<std::string, std::string> remaps;
  std::map<std::string, PortQos> qos;
};

bool is_map_or_absent(const YAML::Node& n) {
  return !n.IsDefined() || n.IsNull() || n.IsMap();
}

}  // namespace

// Reads a launch file into a Launch; collects every error it finds.
class LaunchBuilder {
 public:
  LaunchBuilder(std::string file, LaunchOptions options)
      : file_(std::move(file)), options_(std::move(options)) {}

  Result<std::unique_ptr<Launch>, Launch::Errors> build(YAML::Node root) {
    if (!root.IsMap())
      return fail(file_ +
                  ": a launch file is a mapping (clock, executor, run, robots, components)");
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

  Result<std::unique_ptr<Launch>, Launch::Errors> fail(std::string message) {
    errors_.push_back(std::move(message));
    return make_unexpected(errors_);
  }

 private:
  std::string out_dir() const {
    if (!options_.out_dir.empty()) return options_.out_dir;
    std::string stem = file_.substr(file_.find_last_of('/') + 1);
    stem = stem.substr(0, stem.find('.'));
    return "runs/" + (stem.empty() ? std::string("run") : stem);
  }

  // --set name.key=value: onto the YAML tree before it is read, so that the value goes
  // through the same checks as the file's own.
  void apply_overrides(YAML::Node& root) {
    auto errors = apply_launch_overrides(root, options_.overrides, file_);
    errors_.insert(errors_.end(), errors.begin(), errors.end());
  }

  void merge(const ParamReader& reader) {
    errors_.insert(errors_.end(), reader.errors().begin(), reader.errors().end());
  }

  void read_settings(const YAML::Node& root, LaunchSettings& s) {
    ParamReader top = make_param_reader(root, file_, "(top level)");
    std::string clock = "wall";
    top.choice("clock", clock, {"wall", "sim"});
    s.clock = clock == "sim" ? ClockType::kSim : ClockType::kWall;
    // the sections below are read on their own; mark them known to the top level
    for (const char* section : {"executor", "run", "robots", "components", "security"}) {
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
            ": unknown key; allowed: clock, executor, run, robots, components, security");
    merge(top);

    ParamReader exec = make_param_reader(root["executor"], file_, "executor");
    std::string type = "single_threaded";
    exec.choice("type", type, {"single_threaded", "multi_threaded", "step"});
    uint64_t threads = 2;
    exec.optional("threads", threads, {1, 64});
    exec.optional("spin_us", s.spin_us, {0, 1e6});
    exec.finish();
    merge(exec);
    s.executor = type == "step"             ? LaunchSettings::ExecutorType::kStep
                 : type == "multi_threaded" ? LaunchSettings::ExecutorType::kMultiThreaded
                                            : LaunchSettings::ExecutorType::kSingleThreaded;
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
    compute_time_.clear();  // unset: decided once the components are known
    const YAML::Node run_node = root["run"];
    if (run_node.IsDefined() && run_node.IsMap() && run_node["compute_time"].IsDefined()) {
      compute_time_ = "charged";
      run.choice("compute_time", compute_time_, {"charged", "free"});
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
    if (compute_time_ == "charged" && s.executor != LaunchSettings::ExecutorType::kStep)
      errors_.push_back(yaml_location(file_, root["run"]) +
                        ": run.compute_time: 'charged' needs executor: {type: step} (sim time); "
                        "on the wall clock compute takes real time anyway");
    if (compute_time_ == "charged" && options_.process != "run")
      errors_.push_back(yaml_location(file_, root["run"]) +
                        ": run.compute_time: 'charged' is for one process (scancrew run); a team "
                        "split over processes runs with compute free (docs/processes.md)");
  }

  // The robots: list, or its first N (LaunchOptions::robot_count, else run.robots).
  void read_robots(const YAML::Node& node, size_t run_robots) {
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

  void read_robot_list(const YAML::Node& node) {
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
      r.choice("kind", robot.kind, {"ground", "multirotor"});
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

  static bool valid_name(const std::string& s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    });
  }

  void read_components(const YAML::Node& node) {
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
      r.required("name", spec.name);
      r.required("type", spec.type);
      r.optional("per_robot", spec.per_robot);
      read_processes(c, spec, r);
      known_subkeys(
          c, spec.path,
          {"name", "type", "per_robot", "process", "params", "remap", "qos", "callback_group"});
      merge(r);
      if (!r.ok()) continue;
      if (!valid_name(spec.name))
        errors_.push_back(yaml_location(file_, c["name"]) + ": " + spec.path + ".name: '" +
                          spec.name + "' is not a name; allowed: letters, digits, '_'");
      if (const auto [it, fresh] = first_with_name.emplace(spec.name, i); !fresh)
        errors_.push_back(yaml_location(file_, c["name"]) + ": " + spec.path + ".name: '" +
                          spec.name + "' names components[" + std::to_string(it->second) +
                          "] too; each component has a name of its own");
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

  // process: a command name or a list of them; default [run, robot] (per-robot) or [run].
  void read_processes(const YAML::Node& c, ComponentSpec& spec, ParamReader& r) {
    static constexpr std::array<std::string_view, 4> kProcesses = {"run", "sim", "robot",
                                                                   "station"};
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

  void known_subkeys(const YAML::Node& c, const std::string& path,
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

  void read_group(const YAML::Node& node, ComponentSpec& spec) {
    if (!node.IsDefined() || node.IsNull()) return;
    ParamReader r = make_param_reader(node, file_, spec.path + ".callback_group");
    r.required("name", spec.group_name);
    std::string type = "mutually_exclusive";
    r.choice("type", type, {"mutually_exclusive", "reentrant"});
    r.finish();
    merge(r);
    spec.group_type = type == "reentrant" ? CallbackGroup::Type::kReentrant
                                          : CallbackGroup::Type::kMutuallyExclusive;
  }

  void read_remaps(const YAML::Node& node, ComponentSpec& spec) {
    if (!node.IsDefined() || node.IsNull()) return;
    if (!node.IsMap()) {
      errors_.push_back(yaml_location(file_, node) + ": " + spec.path +
                        ".remap: must be a mapping port: topic");
      return;
    }
    for (const auto& kv : node) {
      const std::string port = kv.first.Scalar();
      if (!kv.second.IsScalar() || kv.second.Scalar().empty() || kv.second.Scalar() == "/") {
        errors_.push_back(
            yaml_location(file_, kv.first) + ": " + spec.path + ".remap." + port +
            ": remap to nothing; allowed: a topic name, relative (ns/name) or absolute (/name)");
        continue;
      }
      spec.remaps[port] = kv.second.Scalar();
    }
  }

  void read_qos(const YAML::Node& node, ComponentSpec& spec) {
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
      std::string history;
      r.optional("pool_size", pool, {1, 1e6});
      r.optional("depth", depth, {1, 1e6});
      if (kv.second.IsMap() && kv.second["history"].IsDefined()) {
        history = "keep_last";
        r.choice("history", history, {"keep_last", "fail_fast"});
      }
      r.finish();
      merge(r);
      if (pool) q.pool_size = pool;
      if (depth) q.depth = depth;
      if (!history.empty())
        q.history = history == "fail_fast" ? History::kFailFast : History::kKeepLast;
      spec.qos[port] = q;
    }
  }

  void compose(Launch& launch) {
    LaunchSettings& s = launch.settings_;
    if (s.clock == ClockType::kSim)
      launch.clock_ = std::make_shared<SimClock>();
    else
      launch.clock_ = std::make_shared<WallClock>();
    launch.graph_ = std::make_unique<Graph>(launch.clock_);
    std::map<std::string, std::shared_ptr<CallbackGroup>> groups;

    // create every instance (parameter errors are collected, nothing is configured yet)
    struct Pending {
      const ComponentSpec* spec;
      std::unique_ptr<Component> component;
      std::string place;  // the computer it runs on; "" = the world (never charged)
    };
    std::vector<Pending> created;
    const auto team = std::make_shared<const std::vector<TeamMember>>(robots_);
    const auto& registry = ComponentRegistry::instance();
    // a robot process makes the per-robot components of its own robot only
    std::vector<RobotSpec> own = robots_;
    if (options_.process == "robot") {
      own.clear();
      for (const RobotSpec& r : robots_)
        if (r.id == options_.robot_id) own.push_back(r);
      if (own.empty()) {
        std::string ids;
        for (const RobotSpec& r : robots_) ids += (ids.empty() ? "" : ", ") + std::to_string(r.id);
        errors_.push_back(file_ + ": --robot " + std::to_string(options_.robot_id) +
                          ": no such robot in this run; its robots: " + ids);
        return;
      }
    }
    if (!s.station && robots_.size() != 1) {
      errors_.push_back(file_ +
                        ": run.station: false puts the station's components on the one "
                        "robot's computer; this run has " +
                        std::to_string(robots_.size()) + " robots");
      return;
    }
    for (const ComponentSpec& spec : specs_) {
      const std::vector<RobotSpec> owners = spec.per_robot ? own : std::vector<RobotSpec>{{0, ""}};
      bool params_reported = false;
      for (const RobotSpec& robot : owners) {
        ComponentContext ctx;
        ctx.graph = launch.graph_.get();
        ctx.team = team;
        ctx.name = spec.name;
        ctx.ns = robot.ns;
        ctx.robot_id = robot.id;
        ctx.remaps = spec.remaps;
        ctx.qos = spec.qos;
        const std::string group_key =
            robot.ns + "/" + (spec.group_name.empty() ? spec.name : spec.group_name);
        auto& group = groups[group_key];
        if (!group) group = std::make_shared<CallbackGroup>(group_key, spec.group_type);
        ctx.callback_group = group;
        ctx.security_keys = launch.settings_.security_keys;
        // a per-robot component's strings name their robot: "{ns}", "{id}"
        // and every component's, the run directory: "{out}"
        std::vector<std::pair<std::string, std::string>> names = {{"{out}", out_dir()}};
        if (spec.per_robot) {
          names.emplace_back("{ns}", robot.ns);
          names.emplace_back("{id}", std::to_string(robot.id));
        }
        ParamReader params =
            make_param_reader(spec.params, file_, spec.path + ".params", std::move(names));
        const ComponentRegistry::Entry* entry = registry.find(spec.type);
        // a per-robot component runs on its robot; the others on the ground station (or,
        // without one, on the one robot), but for the world's (the simulator, the mission's
        // instruments)
        std::string place = entry->world     ? ""
                            : spec.per_robot ? robot.ns
                            : s.station      ? "station"
                                             : robots_.front().ns;
        auto made = entry->factory(std::move(ctx), params);
        if (!made) {
          // the same parameters go to every robot: report them once
          if (!params_reported)
            errors_.insert(errors_.end(), made.error().begin(), made.error().end());
          params_reported = true;
          continue;
        }
        created.push_back({&spec, std::move(made).value(), std::move(place)});
      }
    }
    for (auto& [key, group] : groups) launch.groups_.push_back(group);
    if (!errors_.empty()) return;

    // configure: endpoints are created, types checked; nothing runs yet
    for (auto& p : created) {
      auto configured = p.component->configure();
      if (!configured) errors_.push_back(file_ + ": " + p.spec->path + ": " + configured.error());
      for (const auto& [port, topic] : p.spec->remaps) {
        const auto& ports = p.component->ports();
        if (std::find(ports.begin(), ports.end(), port) != ports.end()) continue;
        std::string list;
        for (const auto& q : ports) list += (list.empty() ? "" : ", ") + q;
        errors_.push_back(file_ + ": " + p.spec->path + ".remap." + port + ": component '" +
                          p.spec->type + "' has no port '" + port +
                          "'; its ports: " + (list.empty() ? "(none)" : list));
      }
    }
    // a remap error is reported once per spec, not once per robot
    std::sort(errors_.begin(), errors_.end());
    errors_.erase(std::unique(errors_.begin(), errors_.end()), errors_.end());
    for (const std::string& e : launch.graph_->check().errors) errors_.push_back(file_ + ": " + e);
    if (!errors_.empty()) return;

    if (s.executor == LaunchSettings::ExecutorType::kStep) {
      // a mission run in one process charges compute unless the file says otherwise
      const bool mission = std::any_of(specs_.begin(), specs_.end(), [](const ComponentSpec& c) {
        return c.type == "mission_monitor";
      });
      s.compute_time = compute_time_ == "charged" ||
                               (compute_time_.empty() && mission && options_.process == "run")
                           ? ComputeTime::kCharged
                           : ComputeTime::kFree;
      launch.step_executor_ =
          std::make_unique<StepExecutor>(static_cast<SimClock&>(*launch.clock_));
      launch.step_executor_->set_compute_time(s.compute_time, s.charge);
      std::map<std::string, int> places;
      for (auto& p : created) {
        int place = StepExecutor::kWorld;
        if (!p.place.empty()) {
          auto [it, added] = places.try_emplace(p.place, 0);
          if (added) it->second = launch.step_executor_->add_place(p.place);
          place = it->second;
        }
        for (Executable* e : p.component->executables()) launch.step_executor_->add(*e, place);
      }
    }
    for (auto& p : created) {
      if (p.place.empty()) launch.world_components_.insert(p.component->qualified_name());
      launch.components_.push_back(std::move(p.component));
    }
    if (s.executor != LaunchSettings::ExecutorType::kStep) {
      launch.executor_ =
          std::make_unique<Executor>(s.threads, static_cast<int64_t>(s.spin_us * 1e3));
      for (auto& c : launch.components_)
        for (Executable* e : c->executables()) launch.executor_->add(*e);
    }
  }

  std::string file_;
  LaunchOptions options_;
  std::vector<std::string> errors_;
  std::set<std::string> top_known_;
  std::string compute_time_;  // run.compute_time as the file (or --set) gives it; "" unset
  std::vector<RobotSpec> robots_;
  std::vector<ComponentSpec> specs_;
};

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
      progress(static_cast<double>(clock.now_ns() - start) * 1e-9, settings_.duration_s);
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
      progress(elapsed(), settings_.duration_s);
      next_report += settings_.progress_period_s;
    }
  }
  executor_->stop();
  spinner.join();
  return elapsed();
}

}  // namespace scancrew
