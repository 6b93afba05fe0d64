#pragma once

// RunSummary: what a mission's components report for its run directory (metrics.json and
// the closing line of `scancrew run`). Launch::summary() asks every component through
// Component::summarize(); each fills what it knows. The CLI reads the summary and never a
// component's type.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace scancrew {

struct RunSummary {
  // A map a mapper keeps (tsdf_mapper): where its outputs went and what it sent.
  struct Map {
    std::string component;  // the instance name, e.g. "tsdf_mapper"
    uint32_t robot_id = 0;  // 0 for a station's
    std::string mode;       // single | centralized | distributed
    std::string mesh_path, octomap_path;
    double voxel_m = 0;
    uint64_t patch_wire_bytes = 0;  // completed patches as sent
  };
  // A robot's low-level planner: its tours and goals.
  struct Planner {
    uint64_t tours = 0, goals_reached = 0, replans = 0;
  };
  // A robot's odometry estimate (vio): its frames, its tracking losses and their reasons.
  struct Odometry {
    uint64_t frames = 0;
    uint32_t losses = 0;
    uint64_t coasted_frames = 0;                       // bridged by the prediction, not losses
    std::map<std::string, uint32_t> losses_by_reason;  // only reasons that occurred
    double mean_frame_ms = 0, max_frame_ms = 0;
    // scored against the truth by the mission monitor (simulation only; 0 poses: not scored)
    uint64_t scored_poses = 0;
    double truth_distance_m = 0;  // path length over the scored poses
    double ate_rmse_m = 0, ate_max_m = 0, rpe_mean_percent = 0;
  };
  // Two robots' odometry frames against each other (mission monitor, simulation only): how
  // far apart they put one true point near both, over the mission (pose_error.hpp).
  struct FrameMisalignment {
    uint32_t robot_a = 0, robot_b = 0;  // robot ids
    uint64_t samples = 0;
    double mean_m = 0, max_m = 0, last_m = 0, max_yaw_deg = 0;
  };
  // Bodies that touched (team_simulator).
  struct Contacts {
    uint64_t robot_scene = 0, robot_robot = 0;
  };
  // A robot's commands (path_tracker): how old the data behind each cmd_vel was, in ms of
  // the launch's clock. age: publish time minus the capture stamp of the pose it was computed
  // from, every command; first_use: the same, for the first command after each new pose
  // (camera to command). Percentiles within 12.5 % (LatencyHistogram).
  struct CommandLatency {
    uint64_t commands = 0, poses = 0;
    double age_p50_ms = 0, age_p99_ms = 0, age_max_ms = 0;
    double first_use_p50_ms = 0, first_use_p99_ms = 0, first_use_max_ms = 0;
  };
  // The simulator on the wall clock (team_simulator): physics stepped to wall time.
  struct WallClockSim {
    double simulated_s = 0;  // physics time reached
    uint64_t ticks = 0;
    uint64_t late_ticks = 0;    // started more than two physics steps behind the wall
    uint64_t capped_ticks = 0;  // stopped at max_catch_up_s, still behind
    double max_lag_s = 0;       // the most the physics was behind the wall after a tick
  };

  std::vector<Map> maps;                  // in launch order
  std::map<uint32_t, Planner> planners;   // by robot id
  std::map<uint32_t, Odometry> odometry;  // by robot id
  std::vector<FrameMisalignment> frame_misalignment;
  Contacts contacts;
  std::map<uint32_t, CommandLatency> command_latency;  // by robot id
  std::optional<WallClockSim> wall_clock_sim;          // set on the wall clock only
};

}  // namespace scancrew
