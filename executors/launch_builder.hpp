#pragma once

// LaunchBuilder: reads a launch file into a Launch (launch_builder.cpp) and composes it
// (launch_compose.cpp). Private to executors/: Launch::from_file and from_string use it.

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "executors/launch.hpp"
#include "executors/params_impl.hpp"

namespace scancrew {

// Reads a launch file into a Launch; collects every error it finds.
class LaunchBuilder {
 public:
  LaunchBuilder(std::string file, LaunchOptions options)
      : file_(std::move(file)), options_(std::move(options)) {}

  Result<std::unique_ptr<Launch>, Launch::Errors> build(YAML::Node root);

  Result<std::unique_ptr<Launch>, Launch::Errors> fail(std::string message);

 private:
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

  std::string out_dir() const;
  void apply_overrides(YAML::Node& root);
  void merge(const ParamReader& reader);
  void read_settings(const YAML::Node& root, LaunchSettings& s);
  void read_robots(const YAML::Node& node, size_t run_robots);
  void read_robot_list(const YAML::Node& node);
  static bool valid_name(const std::string& s);
  void read_components(const YAML::Node& node);
  void check_name(const YAML::Node& c, const ComponentSpec& spec, size_t index,
                  std::map<std::string, size_t>& first_with_name);
  void read_processes(const YAML::Node& c, ComponentSpec& spec, ParamReader& r);
  void known_subkeys(const YAML::Node& c, const std::string& path,
                     std::initializer_list<std::string_view> allowed);
  void read_group(const YAML::Node& node, ComponentSpec& spec);
  void read_remaps(const YAML::Node& node, ComponentSpec& spec);
  // A mapping port: topic at `path` ("remap", "components[i].remap") into out.
  void read_remap_map(const YAML::Node& node, const std::string& path,
                      std::map<std::string, std::string>& out);
  void read_qos(const YAML::Node& node, ComponentSpec& spec);
  // An instance made, not yet configured: its spec, and where it runs.
  struct Pending {
    const ComponentSpec* spec;
    std::unique_ptr<Component> component;
    std::string place;  // the computer it runs on; "" = the world (never charged)
  };

  void compose(Launch& launch);
  // The robots whose per-robot components this process makes; false (an error) if none.
  bool own_robots(const LaunchSettings& s, std::vector<RobotSpec>& own);
  // Creates every instance and the launch's callback groups; parameter errors collected.
  void create_instances(Launch& launch, const std::vector<RobotSpec>& own,
                        std::vector<Pending>& created);
  // Configures every instance, checks its remaps and the graph; errors collected.
  void configure_instances(Launch& launch, std::vector<Pending>& created);
  void check_launch_remaps(const std::vector<Pending>& created);
  // Makes the launch's executor with the instances' executables; the launch takes the instances.
  void add_executor(Launch& launch, std::vector<Pending>& created);

  std::string file_;
  LaunchOptions options_;
  std::vector<std::string> errors_;
  std::set<std::string> top_known_;
  std::optional<ComputeTime> compute_time_;  // run.compute_time as the file (or --set) gives it
  std::vector<RobotSpec> robots_;
  std::vector<ComponentSpec> specs_;
  // the launch's own remap: every component with the port takes it, unless its own remap
  // names the port (the idea of ROS 2 launch's SetRemap)
  std::map<std::string, std::string> remaps_;
};

}  // namespace scancrew
