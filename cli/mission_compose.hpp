#pragma once

// A mission from a scene, a team and an architecture (scancrew bench explore): the launch
// file's graph is the architecture's (single, centralized: the station maps, extracts ISEs
// and runs TSGA; distributed: each robot maps patches and runs dist-TSGA, with the
// redundancy check), its parameters the robot kind's profile (launch_cfg/profiles/
// <kind>.yaml: component name -> parameters, and <name>_<architecture> for what only one
// architecture reads), the robots the first N of the scene's starts for that kind, and
// nothing else: no per-scene parameter. Teams of more than one robot blank their teammates
// out of the depth (depth_mask).
//
// A mixed team (MissionSpec::team: ground robots and multirotors) takes its robots kind by
// kind in the team's order (ids 1, 2, ... and namespaces r1, r2, ... running on across the
// kinds), each kind's from the first of the scene's starts for that kind, and the profile
// launch_cfg/profiles/mixed.yaml: the per-kind keys (ground_*, multirotor_*) of both
// profiles, and for the keys the kinds share (the map's voxel, truncation and depth range,
// the depth mask's margin, d_v, the monitor's density) the multirotors' values, with the
// ground robots' camera and viewpoint ranges set to that map's range (docs/missions.md,
// "Mixed teams").
//
// The sensor chain: `depth: stereo` adds a stereo_depth component per robot (SGBM on the
// simulator's stereo pair, which then publishes no rendered depth), `pose: vio` a vio
// component per robot, with every stage reading its `odom` for `pose`. Their parameters are
// the profile's `stereo_depth` and `vio` sections, and a profile section `<name>_stereo` or
// `<name>_vio` sets what a component takes only with that chain (the odometry's camera rate
// and turn rates). Section precedence: the graph's own keys, then <name>_stereo and
// <name>_vio, then <name>, then <name>_<architecture>.
//
// compose_mission() returns the launch file's text (YAML), or what is wrong (a team size or a
// reconstruction map the architecture does not take, a scene that cannot be read or lists
// fewer starts than robots, a profile that cannot be read).

#include <cstddef>
#include <string>
#include <vector>

#include "cli/choices.hpp"
#include "core/result.hpp"
#include "core/robot/robot_kind.hpp"

namespace scancrew::cli {

// The robots of one kind in a team.
struct TeamPart {
  robot::RobotKind kind = robot::RobotKind::kGround;
  size_t robots = 0;
};

struct MissionSpec {
  std::string scene_path;
  robot::RobotKind kind = robot::RobotKind::kGround;
  size_t robots = 1;
  // a team of one or more kinds, in this order (a mission file's `team:`); empty: `robots`
  // robots of `kind`
  std::vector<TeamPart> team;
  Architecture arch = Architecture::kDistributed;
  double duration_s = 600;
  int seed = 1;  // the simulator's and the low-level planners' seed
  // > 0: a second, finer TSDF map of the same depth (component `recon`) whose mesh is the
  // mission's result, scored at the planning map's e_max; nothing plans on it. Single and
  // centralized only (a distributed team has no map that all the depth reaches).
  double reconstruction_voxel_m = 0;
  // "": <kind>.yaml under profile_root (mixed.yaml for a team of more than one kind). A
  // mission file's profile_root is the directory profiles/ beside its own directory (for
  // launch_cfg/missions/x.yaml: launch_cfg/profiles), whatever the working directory;
  // bench explore's, launch_cfg/profiles under the working directory.
  std::string profile_path;
  std::string profile_root = "launch_cfg/profiles";
  std::string compute_time;  // "": the launch's default (charged for a mission)
  // the depth and pose sources: rendered depth and true pose, or the chain of the thesis's
  // real robots (Table 5.4): SGBM (stereo_depth) and each robot's odometry (vio)
  DepthSource depth = DepthSource::kRendered;
  PoseSource pose = PoseSource::kTruth;
};

// The team a spec describes: its `team`, or its `robots` robots of `kind`.
std::vector<TeamPart> team_parts(const MissionSpec& spec);

Result<std::string, std::string> compose_mission(const MissionSpec& spec);

// The text of the launch file at `path`, for Launch::from_string: as written, or, for a
// mission file (a mapping with the one key `mission`), the composed mission:
//   mission: {scene: ../scenes/parking_lot.yaml, kind: ground, robots: 2,
//             architecture: distributed, duration_s: 900, seed: 1}
// (scene relative to the mission file's directory; the composed file names it absolute)
// scene, kind, robots and architecture are required; duration_s (600), seed (1),
// reconstruction_voxel_m (none), depth (rendered | stereo) and pose (truth | vio) are not; any
// other key, and a kind or an architecture that its table (kRobotKindNames, kArchitectureNames)
// does not name, is an error naming it. A mixed team replaces kind and robots by `team`, the robots
// of each kind in order:
//   mission: {scene: ../scenes/powerplant.yaml, team: {ground: 2, multirotor: 3},
//             architecture: centralized}
// (team with kind or robots: an error; each count >= 1).
// `robots` > 0 (scancrew run --robots N) composes a mission file with N robots instead of its
// own count; a mission file with `team` refuses it (which kind would grow is the file's to
// say).
// scancrew run and graph read launch files through it.
Result<std::string, std::string> launch_file_text(const std::string& path, size_t robots = 0);

}  // namespace scancrew::cli
