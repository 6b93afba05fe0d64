// LaunchBuilder::compose: the launch's clock, graph, callback groups and component
// instances (created, configured, checked), then the executor that runs them.

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "executors/launch_builder.hpp"
#include "executors/log.hpp"
#include "executors/registry.hpp"

namespace scancrew {

namespace {

// The keys of component `name`'s parameters that --set gives ("name.key=value").
std::set<std::string> keys_set_of(const std::string& name,
                                  const std::vector<std::string>& overrides) {
  std::set<std::string> keys;
  for (const std::string& o : overrides) {
    const size_t dot = o.find('.'), eq = o.find('=');
    if (dot == std::string::npos || eq == std::string::npos || dot > eq) continue;
    if (o.compare(0, dot, name) == 0 && dot == name.size())
      keys.insert(o.substr(dot + 1, eq - dot - 1));
  }
  return keys;
}

}  // namespace

void LaunchBuilder::compose(Launch& launch) {
  LaunchSettings& s = launch.settings_;
  if (s.clock == ClockType::kSim)
    launch.clock_ = std::make_shared<SimClock>();
  else
    launch.clock_ = std::make_shared<WallClock>();
  launch.graph_ = std::make_unique<Graph>(launch.clock_);

  // create every instance (parameter errors are collected, nothing is configured yet)
  std::vector<Pending> created;
  std::vector<RobotSpec> own;
  if (!own_robots(s, own)) return;
  create_instances(launch, own, created);
  if (!errors_.empty()) return;

  configure_instances(launch, created);
  if (!errors_.empty()) return;

  add_executor(launch, created);
}

bool LaunchBuilder::own_robots(const LaunchSettings& s, std::vector<RobotSpec>& own) {
  // a robot process makes the per-robot components of its own robot only
  own = robots_;
  if (options_.process == "robot") {
    own.clear();
    for (const RobotSpec& r : robots_)
      if (r.id == options_.robot_id) own.push_back(r);
    if (own.empty()) {
      std::string ids;
      for (const RobotSpec& r : robots_) ids += (ids.empty() ? "" : ", ") + std::to_string(r.id);
      errors_.push_back(file_ + ": --robot " + std::to_string(options_.robot_id) +
                        ": no such robot in this run; its robots: " + ids);
      return false;
    }
  }
  if (!s.station && robots_.size() != 1) {
    errors_.push_back(file_ +
                      ": run.station: false puts the station's components on the one "
                      "robot's computer; this run has " +
                      std::to_string(robots_.size()) + " robots");
    return false;
  }
  return true;
}

void LaunchBuilder::create_instances(Launch& launch, const std::vector<RobotSpec>& own,
                                     std::vector<Pending>& created) {
  const LaunchSettings& s = launch.settings_;
  std::map<std::string, std::shared_ptr<CallbackGroup>> groups;
  const auto team = std::make_shared<const std::vector<TeamMember>>(robots_);
  const auto& registry = ComponentRegistry::instance();
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
      ctx.remaps = remaps_;
      for (const auto& [port, topic] : spec.remaps) ctx.remaps[port] = topic;
      ctx.qos = spec.qos;
      const std::string group_key =
          robot.ns + "/" + (spec.group_name.empty() ? spec.name : spec.group_name);
      auto& group = groups[group_key];
      if (!group) group = std::make_shared<CallbackGroup>(group_key, spec.group_type);
      ctx.callback_group = group;
      ctx.security_keys = launch.settings_.security_keys;
      // input files are relative to the launch file (Component::input_path)
      ctx.launch_dir = std::filesystem::path(file_).parent_path().string();
      ctx.set_keys = keys_set_of(spec.name, options_.overrides);
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
}

void LaunchBuilder::configure_instances(Launch& launch, std::vector<Pending>& created) {
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
  check_launch_remaps(created);
  // a remap error is reported once per spec, not once per robot
  std::sort(errors_.begin(), errors_.end());
  errors_.erase(std::unique(errors_.begin(), errors_.end()), errors_.end());
  for (const std::string& e : launch.graph_->check().errors) errors_.push_back(file_ + ": " + e);
}

void LaunchBuilder::check_launch_remaps(const std::vector<Pending>& created) {
  // the launch's own remap applies to every component with the port: one that no component
  // has does nothing: a misspelt port, or a graph that reads none (a test's part of a graph;
  // a process of a team split over processes holds part of it, so only the whole graph is
  // checked). A warning, not an error: such a launch runs as written
  if (options_.process != "run") return;
  for (const auto& remap : remaps_) {
    const std::string& port = remap.first;
    const bool used = std::any_of(created.begin(), created.end(), [&](const Pending& p) {
      const auto& ports = p.component->ports();
      return std::find(ports.begin(), ports.end(), port) != ports.end();
    });
    if (!used)
      SCANCREW_LOG_WARN("%s: remap.%s: no component has port '%s'; the remap does nothing",
                        file_.c_str(), port.c_str(), port.c_str());
  }
}

void LaunchBuilder::add_executor(Launch& launch, std::vector<Pending>& created) {
  LaunchSettings& s = launch.settings_;
  if (s.executor == LaunchSettings::ExecutorType::kStep) {
    // a mission run in one process charges compute unless the file says otherwise
    const bool mission = std::any_of(specs_.begin(), specs_.end(), [](const ComponentSpec& c) {
      return c.type == "mission_monitor";
    });
    s.compute_time = compute_time_.value_or(
        mission && options_.process == "run" ? ComputeTime::kCharged : ComputeTime::kFree);
    launch.step_executor_ = std::make_unique<StepExecutor>(static_cast<SimClock&>(*launch.clock_));
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
    launch.executor_ = std::make_unique<Executor>(s.threads, static_cast<int64_t>(s.spin_us * 1e3));
    for (auto& c : launch.components_)
      for (Executable* e : c->executables()) launch.executor_->add(*e);
  }
}

}  // namespace scancrew
