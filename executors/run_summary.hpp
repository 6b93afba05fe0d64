#pragma once

// RunSummary: what a mission's components report for its run directory (metrics.json and
// the closing line of `scancrew run`). Launch::summary() asks every component through
// Component::summarize(); each fills what it knows. The CLI reads the summary and never a
// component's type.

#include <cstdint>
#include <map>
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
    std::map<std::string, uint32_t> losses_by_reason;  // only reasons that occurred
    double mean_frame_ms = 0, max_frame_ms = 0;
  };
  // Bodies that touched (team_simulator).
  struct Contacts {
    uint64_t robot_scene = 0, robot_robot = 0;
  };

  std::vector<Map> maps;                  // in launch order
  std::map<uint32_t, Planner> planners;   // by robot id
  std::map<uint32_t, Odometry> odometry;  // by robot id
  Contacts contacts;
};

}  // namespace scancrew
