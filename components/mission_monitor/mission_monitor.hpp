#pragma once

// MissionMonitor: watches a team mission from outside the robots' graphs (one instance,
// per_robot: false) and decides when it is over. It is what `scancrew run --out DIR` reads
// to fill the run directory (docs/missions.md): each robot's ground-truth path, the share
// of the scene's surface its map has seen over time (surface_coverage.hpp), its ISEs left,
// its state (msg::RobotState from the low-level planner) and how often it asked to replan.
//
// The mission is complete (thesis 2.4: the ISE stopping criterion) when every ISE source —
// each robot's ise_extractor (maps: per_robot, none) or the station's (shared) — reports
// `complete` (C_ins empty over its consecutive updates); the completion time is the sim
// time of the last of them. It is stalled when no source is complete but every robot has
// been idle or done for stall_timeout_s (nothing left it can reach). finished() then turns
// true, with the reason; the caller stops the launch (Launch::run's stop_when).
//
// Lost robots: a robot whose latest state is kLost (the dds_bridge reports a teammate whose
// process died) is left out of both tests: with per-robot sources the mission is complete
// when every robot not lost reports complete, and a lost robot does not keep "every robot
// idle" from holding. With every robot lost the mission is not complete (logged once); it
// stalls once the last of them has been lost for stall_timeout_s. A robot that publishes a
// state other than kLost again counts again. (maps: shared: the one source decides, as
// before.)
//
// Odometry: where the robots run on an estimated pose (the port `pose` of /<ns> resolves to
// another topic than /<ns>/pose_gt, e.g. remap pose: odom), that pose is scored against the
// truth, per robot and between robots (pose_error.hpp), into RunSummary::odometry and
// frame_misalignment.
//
// Inputs, per robot ns: /<ns>/pose_gt, /<ns>/robot_state, the robot's `pose` if not pose_gt, and
// /<ns>/map, /<ns>/ises (maps: per_robot), /<ns>/ises only (maps: none: a process that cannot see
// the robots' maps, such as a team's simulator process; MapUpdate does not cross processes, so the
// coverage stays "not measured", -1) or /map, /ises (maps: shared).
// Parameters: scene ("" or maps: none = no coverage estimate), coverage_density_per_m2,
// coverage_truncation_share, coverage_period_s, path_period_s, maps, stop_when_complete,
// stall_timeout_s, eval_density_per_m2 and eval_e_max_m (for the final evaluation of the mesh
// by the caller),
// visibility_rays (the ground truth's mesh visibility test, both; sim/surface_sampler.hpp).

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "components/mission_monitor/pose_error.hpp"
#include "components/mission_monitor/surface_coverage.hpp"
#include "core/enum_names.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/map_msgs.hpp"
#include "interfaces/map_update.hpp"
#include "interfaces/nav_msgs.hpp"
#include "report/run_files.hpp"
#include "report/time_breakdown.hpp"

namespace scancrew::mission_monitor {

// Whose maps and ISEs the monitor watches (param `maps`; see above).
enum class MapSources : uint8_t { kPerRobot, kShared, kNone };

inline constexpr EnumNames<MapSources, 3> kMapSourcesNames = {{{MapSources::kPerRobot, "per_robot"},
                                                               {MapSources::kShared, "shared"},
                                                               {MapSources::kNone, "none"}}};

class MissionMonitor final : public Component {
 public:
  // not on a robot or the station: never charged compute (StepExecutor)
  static constexpr bool kWorld = true;
  static constexpr std::string_view kDescription =
      "watches a team mission: paths, coverage over time, ISEs left, completion (run reports)";
  struct Config {
    std::string scene;                        // scene YAML for the coverage estimate; "" = none
    double coverage_density_per_m2 = 50;      // ground-truth points for the estimate
    double coverage_truncation_share = 0.99;  // surface_coverage.hpp
    double coverage_period_s = 5.0;
    double path_period_s = 0.5;
    // per_robot | shared (centralized: the station's map) | none (per-robot ISEs, no maps)
    MapSources maps = MapSources::kPerRobot;
    bool stop_when_complete = true;
    double stall_timeout_s = 60.0;        // 0: never stop for a stall
    double eval_density_per_m2 = 2000.0;  // the final mesh evaluation (scancrew run --out)
    // its e_max: 0 takes each mapper's r_v·√3/2 (thesis 5.4); a table's e_max otherwise
    double eval_e_max_m = 0.0;
    int visibility_rays = 64;  // ground truth: the mesh visibility test; 0: off
  };
  static Config read_config(ParamReader& p);

  struct RobotProgress {
    uint32_t id = 0;
    std::string ns;
    robot::RobotKind kind = robot::RobotKind::kGround;
    msg::RobotState::Mode mode = msg::RobotState::Mode::kIdle;
    bool have_state = false;
    double path_length_m = 0;
    double coverage = -1;  // < 0: not measured yet (or no scene)
    // of the ground truth the team's robot kinds can observe (eval/team_reachable.hpp)
    double coverage_reachable = -1;
    uint64_t ises_left = 0;
    bool have_ises = false;
    bool complete = false;
    // entries into kPlanning (the robot awaiting a plan): metrics.json's "replans" where no
    // low-level planner of the process says how many it asked for (a team split over processes)
    uint64_t planning_requests = 0;
    bool backing_off = false;    // the latest state's
    uint32_t held_by_robot = 0;  // the latest state's
    // a map this robot's depth reaches has integrated one of its images (maps: none: true)
    bool integrated = false;
    report::TimeBreakdown time;  // where its mission time went (time_breakdown.hpp)
  };

  MissionMonitor(ComponentContext context, Config config);

  const Config& config() const { return config_; }
  // Thread-safe snapshots of what was observed (the executor may run in another thread).
  std::vector<RobotProgress> robots() const;
  std::vector<report::PathSample> paths() const;
  std::vector<report::CoverageSample> coverage() const;
  bool finished() const;
  std::string stop_reason() const;  // "complete", "stalled" or "" (still running)
  std::optional<double> completion_time_s() const;
  // "r1 moving 87 % 120 ISE · r2 planning 85 % 130 ISE" for the progress line.
  std::string status_line() const;
  // Accounts the time since the last path tick to each robot's breakdown, so that the
  // breakdowns sum to the mission time (after the run, before reading robots()).
  void close_time_breakdown();
  // The robots (namespaces) no map has integrated a depth image of, among those not lost
  // (maps: none: none).
  std::vector<std::string> robots_without_depth() const;
  // Whether completion waits until a map has integrated a depth image of every robot (the
  // default). Off in one process of a team split over processes, whose maps are in other
  // processes (MapUpdate does not cross them). Set before the run.
  void set_depth_required(bool required) { depth_required_ = required; }
  // The team's kinds and start positions (the reachable ground truth's, team_reachable.hpp).
  std::vector<eval::TeamStart> team_starts() const;
  // The odometry's error against the truth (when the robots run on one; see above).
  void summarize(RunSummary& into) const override;

 private:
  struct Source {
    std::shared_ptr<const tsdf::MapSnapshot> map;
    uint64_t map_version_measured = ~0ull;
    bool complete = false;
    uint64_t ises_left = 0;
    bool have_ises = false;
  };
  Result<void, std::string> on_configure() override;
  void on_activate() override;
  void on_pose(size_t robot, const msg::Odometry& odom);
  void on_estimate(size_t robot, const msg::Odometry& odom);
  void on_state(size_t robot, const msg::RobotState& state);
  void on_ises(size_t source, const msg::IseSet& ises);
  void on_map(size_t source, const msg::MapUpdate& update);
  void on_path_tick();
  void on_coverage_tick();
  void account_time(double t);  // with mutex_ held
  void check_finished();
  double now_s();

  Config config_;
  std::optional<SurfaceCoverage> truth_;
  mutable std::mutex mutex_;
  std::vector<RobotProgress> robots_;
  std::vector<Source> sources_;  // one per robot (per_robot, none) or one (shared)
  std::vector<msg::Odometry> last_pose_;
  std::vector<bool> have_pose_;
  std::vector<double> idle_since_s_;  // < 0: not idle
  double last_lost_s_ = -1;           // when the latest robot was lost (< 0: none yet)
  bool all_lost_logged_ = false;
  std::optional<PoseError> pose_error_;  // robots on an estimated pose only
  std::vector<report::PathSample> paths_;
  std::vector<report::CoverageSample> coverage_;
  std::string stop_reason_;
  std::optional<double> completion_time_s_;
  int64_t start_ns_ = 0;    // the mission's time 0: activation
  double accounted_s_ = 0;  // the breakdowns cover [0, accounted_s_]
  bool no_depth_logged_ = false;
  bool depth_required_ = true;
};

}  // namespace scancrew::mission_monitor
