#include "cli/mission_compose.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string_view>
#include <vector>

#include "executors/params_impl.hpp"
#include "sim/scene.hpp"

namespace scancrew::cli {

namespace {

struct ComponentPlan {
  std::string name, type;
  bool per_robot = true;
  YAML::Node params = YAML::Node(YAML::NodeType::Map);
  YAML::Node remap;  // null: none
};

// A number as YAML writes it by hand (yaml-cpp would write 0.05 as 0.050000000000000003).
YAML::Node number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return YAML::Node(std::string(buf));
}

// [x, y, z] in flow style.
YAML::Node flow_vector(const msg::Vec3& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  n.SetStyle(YAML::EmitterStyle::Flow);
  n.push_back(number(v.x));
  n.push_back(number(v.y));
  n.push_back(number(v.z));
  return n;
}

// The scene's path in a composed file: absolute, as the file may be written anywhere (bench
// explore's run directories) and a relative path in a launch file is relative to its directory.
std::string composed_scene_path(const MissionSpec& s) {
  return std::filesystem::absolute(s.scene_path).lexically_normal().string();
}

// The simulator and each robot's sensor chain (odometry, stereo depth, teammates masked).
void add_sensor_chain(const MissionSpec& s, bool masked, std::vector<ComponentPlan>& g) {
  ComponentPlan sim{.name = "team_simulator", .type = "team_simulator", .per_robot = false};
  sim.params["scene"] = composed_scene_path(s);
  sim.params["seed"] = s.seed;
  const bool stereo = s.depth == DepthSource::kStereo;
  const bool vio = s.pose == PoseSource::kVio;
  sim.params["publish_stereo"] = stereo || vio;
  if (stereo) sim.params["publish_depth"] = false;  // the depth is SGBM's
  sim.params["publish_imu"] = vio;                  // only the odometry reads it
  g.push_back(sim);
  if (vio) g.push_back({.name = "vio", .type = "vio"});
  if (stereo) g.push_back({.name = "stereo_depth", .type = "stereo_depth"});
  if (masked) g.push_back({.name = "depth_mask", .type = "depth_mask"});
}

// The graph of an architecture, before the profile's parameters.
std::vector<ComponentPlan> architecture_graph(const MissionSpec& s, const sim::SceneSpec& scene,
                                              bool masked) {
  const bool centralized = s.arch == Architecture::kCentralized;
  const bool single = s.arch == Architecture::kSingle;
  const bool distributed = s.arch == Architecture::kDistributed;
  std::vector<ComponentPlan> g;
  add_sensor_chain(s, masked, g);

  ComponentPlan mapper{.name = "tsdf_mapper", .type = "tsdf_mapper", .per_robot = !centralized};
  mapper.params["mode"] = to_string(s.arch);
  if (masked) mapper.params["depth_topic"] = "depth_masked";
  // with a reconstruction map, mesh.ply is its mesh (cli/mesh_scores.cpp, best_mesh) and the
  // planning map's is kept beside it
  mapper.params["mesh_path"] = distributed                    ? "{out}/mesh_{ns}.ply"
                               : s.reconstruction_voxel_m > 0 ? "{out}/mesh_map.ply"
                                                              : "{out}/mesh.ply";
  mapper.params["octomap_path"] = distributed ? "{out}/map_{ns}.bt" : "{out}/map.bt";
  g.push_back(mapper);
  if (s.reconstruction_voxel_m > 0) {
    // the reconstruction: the same depth in a finer map whose mesh is the result (the
    // profile's tsdf_mapper section fills the rest). Its truncation is 5 of its voxels: at the
    // multirotors' 8 m range 3 sigma of the depth noise is 0.47 m (docs/missions.md, "A finer
    // reconstruction map"). Nothing reads its map: it publishes none, only its mesh is kept.
    ComponentPlan recon{.name = "recon", .type = "tsdf_mapper", .per_robot = !centralized};
    recon.params["mode"] = to_string(s.arch);
    if (masked) recon.params["depth_topic"] = "depth_masked";
    recon.params["voxel_m"] = number(s.reconstruction_voxel_m);
    recon.params["truncation_m"] = number(5 * s.reconstruction_voxel_m);
    recon.params["publish_map"] = false;
    recon.params["mesh_path"] = "{out}/mesh_recon.ply";
    g.push_back(recon);
  }
  // the ISE criterion's bound: the scene's bounds are the region to reconstruct. Outdoors
  // the floor runs on past them, and its edge, with unknown space beyond, would stay an
  // ISE for ever (docs/ise.md, "The region to reconstruct")
  ComponentPlan ise{.name = "ise_extractor", .type = "ise_extractor", .per_robot = !centralized};
  ise.params["region_min_m"] = flow_vector(scene.min_m);
  ise.params["region_max_m"] = flow_vector(scene.max_m);
  g.push_back(ise);

  ComponentPlan planner{.name = "high_level_planner",
                        .type = "high_level_planner",
                        .per_robot = !centralized && !single};
  planner.params["algorithm"] = distributed ? "dist_tsga" : "tsga";
  if (single) {
    // the one robot's clusters and ISEs, as launch_cfg/missions/parking_lot_1_single.yaml
    planner.remap["clusters"] = "/r1/clusters";
    planner.remap["ises"] = "/r1/ises";
  }
  g.push_back(planner);

  ComponentPlan low{.name = "low_level_planner", .type = "low_level_planner"};
  low.params["redundancy_check"] = distributed;
  if (centralized) {
    low.remap["plan"] = "/plan";
    low.remap["map"] = "/map";
    low.remap["ises"] = "/ises";
  } else if (single) {
    low.remap["plan"] = "/plan";
  }
  g.push_back(low);
  ComponentPlan tracker{.name = "path_tracker", .type = "path_tracker"};
  tracker.params["publish_state"] = false;  // nothing in a mission reads tracker_state
  g.push_back(tracker);

  ComponentPlan monitor{.name = "mission_monitor", .type = "mission_monitor", .per_robot = false};
  monitor.params["scene"] = composed_scene_path(s);
  if (centralized) monitor.params["maps"] = "shared";
  g.push_back(monitor);
  return g;
}

// Merges the profile's section `key` (a mapping) into params; the graph's own keys win.
void merge_section(const YAML::Node& profile, const std::string& key, YAML::Node& params) {
  const YAML::Node section = profile[key];
  if (!section.IsDefined() || !section.IsMap()) return;
  for (const auto& kv : section) {
    const std::string k = kv.first.Scalar();
    if (!params[k].IsDefined()) params[k] = kv.second;
  }
}

size_t team_size(const std::vector<TeamPart>& parts) {
  size_t n = 0;
  for (const TeamPart& p : parts) n += p.robots;
  return n;
}

// Refuses a spec whose reconstruction map or team size does not fit its architecture, or
// whose team lists a kind twice or none of a kind.
Result<void, std::string> check_spec(const MissionSpec& s) {
  if (s.reconstruction_voxel_m > 0 && s.arch == Architecture::kDistributed)
    return make_unexpected(
        "reconstruction_voxel_m: a distributed team has no map that all the depth reaches; "
        "single or centralized only");
  for (size_t i = 0; i < s.team.size(); ++i) {
    const std::string kind = robot::to_string(s.team[i].kind);
    if (s.team[i].robots == 0)
      return make_unexpected("team: " + kind + ": 0 robots; a kind in the team has 1 or more");
    for (size_t j = 0; j < i; ++j)
      if (s.team[j].kind == s.team[i].kind)
        return make_unexpected("team: " + kind + " is listed twice");
  }
  const size_t n = team_size(team_parts(s));
  if (n == 0 || (s.arch == Architecture::kSingle && n != 1))
    return make_unexpected("architecture " + to_string(s.arch) + " with " + std::to_string(n) +
                           " robots: single takes 1, the others 1 or more");
  return {};
}

// Reads the profile at profile_path: a mapping of component sections.
Result<YAML::Node, std::string> read_profile(const std::string& profile_path) {
  const auto profile_text = read_text_file(profile_path);
  if (!profile_text)
    return make_unexpected(profile_path + ": cannot read the profile: " + profile_text.error());
  auto profile = parse_yaml(*profile_text, profile_path);
  if (!profile) return make_unexpected(profile.error());
  if (!profile->IsMap()) return make_unexpected(profile_path + ": a profile is a mapping");
  // every section names a component of some mission's graph, or <name>_<architecture>,
  // <name>_stereo or <name>_vio
  static constexpr std::array<std::string_view, 10> kNames = {
      "team_simulator",     "vio",
      "stereo_depth",       "depth_mask",
      "tsdf_mapper",        "ise_extractor",
      "high_level_planner", "low_level_planner",
      "path_tracker",       "mission_monitor"};
  for (const auto& kv : *profile) {
    const std::string key = kv.first.Scalar();
    bool known = false;
    for (const std::string_view n : kNames) {
      const std::string name(n);
      known = known || key == name || key == name + "_stereo" || key == name + "_vio";
      for (const auto& [arch, arch_name] : kArchitectureNames)
        known = known || key == name + "_" + std::string(arch_name);
    }
    if (!known || !kv.second.IsMap())
      return make_unexpected(yaml_location(profile_path, kv.first) + ": '" + key +
                             "' is no component of a mission (a mapping of its parameters); "
                             "allowed: team_simulator, vio, stereo_depth, depth_mask, "
                             "tsdf_mapper, ise_extractor, high_level_planner, "
                             "low_level_planner, path_tracker, mission_monitor, each "
                             "optionally with _single, _centralized, _distributed, _stereo "
                             "or _vio");
  }
  return *profile;
}

// The launch file's run: section.
YAML::Node run_section(const MissionSpec& s) {
  YAML::Node run(YAML::NodeType::Map);
  run["duration_s"] = number(s.duration_s);
  run["sim_step_s"] = number(0.05);
  run["progress_period_s"] = number(20.0);
  if (!s.compute_time.empty()) run["compute_time"] = s.compute_time;
  // one robot alone has no ground station: its map, ISEs and plans run on board
  if (s.arch == Architecture::kSingle) run["station"] = false;
  return run;
}

// "3 multirotor" or "2 ground + 3 multirotor"
std::string team_text(const std::vector<TeamPart>& parts) {
  std::string t;
  for (const TeamPart& p : parts)
    t += (t.empty() ? "" : " + ") + std::to_string(p.robots) + " " + robot::to_string(p.kind);
  return t;
}

// The launch file's entry of robot i (from 0), at the scene's start pose.
YAML::Node robot_entry(size_t i, robot::RobotKind kind, const sim::StartPose& start_pose) {
  YAML::Node r(YAML::NodeType::Map);
  r["id"] = i + 1;
  r["namespace"] = "r" + std::to_string(i + 1);
  r["kind"] = robot::to_string(kind);
  YAML::Node start(YAML::NodeType::Sequence);
  start.SetStyle(YAML::EmitterStyle::Flow);
  start.push_back(number(start_pose.position_m.x));
  start.push_back(number(start_pose.position_m.y));
  start.push_back(number(start_pose.position_m.z));
  start.push_back(number(std::round(start_pose.yaw_rad * 180.0 / M_PI * 1e6) / 1e6));
  r["start"] = start;
  r.SetStyle(YAML::EmitterStyle::Flow);
  return r;
}

// The launch file's entry of a component, with the profile's parameters merged in.
YAML::Node component_entry(ComponentPlan& c, const MissionSpec& s, YAML::Node& profile) {
  // the reconstruction map takes the planning map's parameters where it sets none
  const std::string section = c.name == "recon" ? "tsdf_mapper" : c.name;
  if (c.name == "mission_monitor" && s.reconstruction_voxel_m > 0) {
    // both meshes scored at the planning map's e_max, the thesis's (r_v sqrt(3) / 2)
    // (the profile's value: a --set of the voxel does not move it)
    const YAML::Node voxel = profile["tsdf_mapper"]["voxel_m"];
    try {
      if (voxel.IsDefined() && voxel.IsScalar())
        c.params["eval_e_max_m"] = number(voxel.as<double>() * std::sqrt(3.0) / 2);
    } catch (const YAML::Exception&) {  // not a number: the mapper refuses it by name
    }
  }
  if (s.depth == DepthSource::kStereo) merge_section(profile, section + "_stereo", c.params);
  if (s.pose == PoseSource::kVio) merge_section(profile, section + "_vio", c.params);
  merge_section(profile, section, c.params);
  merge_section(profile, section + "_" + to_string(s.arch), c.params);
  YAML::Node n(YAML::NodeType::Map);
  if (c.name != c.type) n["name"] = c.name;  // one of its type: named by it
  n["type"] = c.type;
  if (!c.per_robot) n["per_robot"] = false;
  if (c.remap.IsDefined() && c.remap.IsMap()) n["remap"] = c.remap;
  if (c.params.size() > 0) n["params"] = c.params;
  return n;
}

// The value of `names` that v names; an error (after `where`) listing the names if none.
template <class E, size_t N>
Result<E, std::string> named(const YAML::Node& v, const EnumNames<E, N>& names,
                             const std::string& where) {
  const std::string name = v.as<std::string>();
  if (const auto value = value_of(names, name)) return *value;
  return make_unexpected(where + ": '" + name +
                         "' is not allowed; allowed: " + joined_names(names));
}

// Reads the mission file's `team: {<kind>: <count>, ...}` into spec.team, in its order.
Result<void, std::string> read_team(MissionSpec& spec, const YAML::Node& v,
                                    const std::string& where) {
  if (!v.IsMap() || v.size() == 0)
    return make_unexpected(where +
                           ": a mapping of robot kind -> count, e.g. {ground: 2, "
                           "multirotor: 3}");
  for (const auto& kv : v) {
    auto kind = named(kv.first, robot::kRobotKindNames, where);
    if (!kind) return make_unexpected(kind.error());
    spec.team.push_back({.kind = *kind, .robots = kv.second.as<size_t>()});
  }
  return {};
}

// Reads the mission file's `key: v` into spec; what is wrong (after `where`) if it cannot.
Result<void, std::string> read_mission_key(MissionSpec& spec, const std::string& key,
                                           const YAML::Node& v, const std::string& where) {
  try {
    if (key == "scene") {
      spec.scene_path = v.as<std::string>();
    } else if (key == "kind") {
      auto kind = named(v, robot::kRobotKindNames, where);
      if (!kind) return make_unexpected(kind.error());
      spec.kind = *kind;
    } else if (key == "robots") {
      spec.robots = v.as<size_t>();
    } else if (key == "team") {
      return read_team(spec, v, where);
    } else if (key == "architecture") {
      auto arch = named(v, kArchitectureNames, where);
      if (!arch) return make_unexpected(arch.error());
      spec.arch = *arch;
    } else if (key == "duration_s") {
      spec.duration_s = v.as<double>();
    } else if (key == "seed") {
      spec.seed = v.as<int>();
    } else if (key == "reconstruction_voxel_m") {
      spec.reconstruction_voxel_m = v.as<double>();
    } else if (key == "depth") {
      auto depth = named(v, kDepthSourceNames, where);
      if (!depth) return make_unexpected(depth.error());
      spec.depth = *depth;
    } else if (key == "pose") {
      auto pose = named(v, kPoseSourceNames, where);
      if (!pose) return make_unexpected(pose.error());
      spec.pose = *pose;
    } else {
      return make_unexpected(where +
                             ": unknown key; allowed: scene, kind, robots (or team), "
                             "architecture, duration_s, seed, reconstruction_voxel_m, depth, "
                             "pose");
    }
  } catch (const YAML::Exception&) {
    return make_unexpected(where + ": not a valid value");
  }
  return {};
}

}  // namespace

std::vector<TeamPart> team_parts(const MissionSpec& spec) {
  if (!spec.team.empty()) return spec.team;
  return {TeamPart{.kind = spec.kind, .robots = spec.robots}};
}

namespace {

// The launch file's robots: each part's from the first of the scene's starts for its kind.
Result<YAML::Node, std::string> robot_entries(const std::vector<TeamPart>& parts,
                                              const sim::SceneSpec& scene,
                                              const std::string& scene_path) {
  YAML::Node robots(YAML::NodeType::Sequence);
  size_t i = 0;
  for (const TeamPart& p : parts) {
    const auto& starts =
        p.kind == robot::RobotKind::kGround ? scene.starts.ground : scene.starts.multirotor;
    if (starts.size() < p.robots)
      return make_unexpected(scene_path + ": starts." + robot::to_string(p.kind) + " lists " +
                             std::to_string(starts.size()) + " start(s), the team has " +
                             std::to_string(p.robots) + " " + robot::to_string(p.kind) + " robots");
    for (size_t j = 0; j < p.robots; ++j) robots.push_back(robot_entry(i++, p.kind, starts[j]));
  }
  return robots;
}

}  // namespace

Result<std::string, std::string> compose_mission(const MissionSpec& s) {
  if (auto checked = check_spec(s); !checked) return make_unexpected(checked.error());
  auto scene = sim::load_scene(s.scene_path);
  if (!scene) {
    std::string all;
    for (const auto& e : scene.error()) all += (all.empty() ? "" : "; ") + e;
    return make_unexpected(all);
  }
  const std::vector<TeamPart> parts = team_parts(s);
  auto robots = robot_entries(parts, *scene, s.scene_path);
  if (!robots) return make_unexpected(robots.error());
  const std::string profile_name =
      parts.size() > 1 ? "mixed" : std::string(robot::to_string(parts.front().kind));
  const std::string profile_path =
      s.profile_path.empty() ? s.profile_root + "/" + profile_name + ".yaml" : s.profile_path;
  auto profile = read_profile(profile_path);
  if (!profile) return make_unexpected(profile.error());

  YAML::Node root(YAML::NodeType::Map);
  root["clock"] = "sim";
  root["executor"]["type"] = "step";
  root["run"] = run_section(s);
  root["robots"] = *robots;
  // every stage's pose: the simulator's ground truth, or the robot's own odometry
  root["remap"]["pose"] = s.pose == PoseSource::kVio ? "odom" : "pose_gt";
  for (ComponentPlan& c : architecture_graph(s, *scene, team_size(parts) > 1))
    root["components"].push_back(component_entry(c, s, *profile));
  YAML::Emitter out;
  out << root;
  return "# composed by scancrew from scene " + s.scene_path + ", " + team_text(parts) +
         " robot(s), " + to_string(s.arch) + ", depth " + to_string(s.depth) + ", pose " +
         to_string(s.pose) + ", profile " + profile_path + "\n" + out.c_str() + "\n";
}

Result<std::string, std::string> launch_file_text(const std::string& path, size_t robots) {
  const auto text = read_text_file(path);
  if (!text) return make_unexpected(path + ": cannot read the launch file: " + text.error());
  auto root = parse_yaml(*text, path);
  if (!root || !root->IsMap() || !(*root)["mission"].IsDefined()) return *text;
  const YAML::Node m = (*root)["mission"];
  if (root->size() != 1)
    return make_unexpected(path + ": a mission file holds `mission:` and nothing else");
  if (!m.IsMap())
    return make_unexpected(yaml_location(path, m) +
                           ": mission: a mapping of scene, kind, robots (or team), "
                           "architecture, duration_s, seed, reconstruction_voxel_m, depth, "
                           "pose");
  MissionSpec spec;
  for (const auto& kv : m) {
    const std::string key = kv.first.Scalar();
    const std::string where = yaml_location(path, kv.first) + ": mission." + key;
    if (auto read = read_mission_key(spec, key, kv.second, where); !read)
      return make_unexpected(read.error());
  }
  const bool team = m["team"].IsDefined();
  if (team && (m["kind"].IsDefined() || m["robots"].IsDefined()))
    return make_unexpected(path +
                           ": mission.team gives the robots of each kind: it replaces kind and "
                           "robots (give one or the other)");
  const std::vector<const char*> required_keys =
      team ? std::vector<const char*>{"scene", "architecture"}
           : std::vector<const char*>{"scene", "kind", "robots", "architecture"};
  for (const char* required : required_keys)
    if (!m[required].IsDefined())
      return make_unexpected(path + ": mission." + required + " is required");
  if (robots > 0 && team)
    return make_unexpected(path +
                           ": --robots: the mission's team (mission.team) gives each kind's "
                           "count; change it there");
  if (robots > 0) spec.robots = robots;  // --robots N
  if (!(spec.duration_s > 0 && std::isfinite(spec.duration_s)))
    return make_unexpected(path + ": mission.duration_s must be > 0");
  if (m["reconstruction_voxel_m"].IsDefined() &&
      !(spec.reconstruction_voxel_m > 0 && std::isfinite(spec.reconstruction_voxel_m)))
    return make_unexpected(path + ": mission.reconstruction_voxel_m must be > 0");
  // the mission file's paths are relative to its directory; its profiles are in the
  // directory beside it, profiles/ (launch_cfg/missions/ and launch_cfg/profiles/)
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  spec.scene_path = (dir / spec.scene_path).lexically_normal().string();
  spec.profile_root = (dir / ".." / "profiles").lexically_normal().string();
  auto composed = compose_mission(spec);
  if (!composed) return make_unexpected(path + ": " + composed.error());
  return composed;
}

}  // namespace scancrew::cli
