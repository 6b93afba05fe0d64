#pragma once

// The closed-loop traffic scenarios' harness (test_teammate_scenarios.cpp,
// test_obstacle_scenarios.cpp): each robot runs team_simulator -> depth_mask -> tsdf_mapper
// -> low_level_planner -> path_tracker on sim time, with a fixed tour from a test feeder in
// place of the ISE extractor and the high-level planner (it answers every replanning
// request with the tour's remaining goals). Scenes: tests/components/low_level_planner/scenes/.
//   - the test components: the tour feeder ("test_tour_feeder", in the .cpp), a log of what
//     each robot's planner sent ("test_robot_log") and the robots' true poses
//     ("test_pose_probe"); registered once, in traffic_scenario_harness.cpp;
//   - the scene's true geometry (footprints, gaps, the body test);
//   - running a scenario and the checks the scenarios share: every local path against the
//     scene's true geometry (the body without the margin, every 2 cm), the robots apart.
// The figures printed with [figures] are the ones quoted in docs/traffic_policy.md.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "components/low_level_planner/low_level_planner.hpp"
#include "components/path_tracker/path_tracker.hpp"
#include "components/team_simulator/team_simulator.hpp"
#include "core/motion/motion_planner.hpp"
#include "core/motion/obstacle_geometry.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"
#include "interfaces/map_update.hpp"
#include "sim/scene.hpp"

namespace scancrew::low_level_planner::scenario_harness {

using motion::ObstacleGeometry;
using motion::PathCheck;

using Mode = msg::RobotState::Mode;
using ManeuverKind = msg::Maneuver::Kind;

inline double seconds(int64_t ns) {
  return 1e-9 * static_cast<double>(ns);
}

// Keeps what one robot's low-level planner sent: local paths (with the map it had when it
// sent each), maneuvers, and its modes (changes only).
class RobotLog final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "test: keeps local paths (with the map), maneuvers and planner modes";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  RobotLog(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  struct Path {
    double t_s = 0;
    uint64_t plan_id = 0;
    std::vector<msg::Waypoint> waypoints;
    std::shared_ptr<const tsdf::MapSnapshot> map;  // the newest the planner could have had
    int64_t map_stamp_ns = 0;
  };
  struct Maneuver {
    double t_s = 0;
    ManeuverKind kind = ManeuverKind::kResume;
    uint32_t because_of_robot = 0;
  };
  std::vector<Path> paths;
  std::vector<Maneuver> maneuvers;
  std::vector<std::pair<double, Mode>> modes;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::MapUpdate>("map", {.depth = 1}, [this](Sample<msg::MapUpdate>&& s) {
      if (s->map == nullptr) return;
      map_ = s->map;
      map_stamp_ns_ = s->header.stamp_ns;
    });
    create_subscription<msg::LocalPath>(
        "local_path", {.depth = 4}, [this](Sample<msg::LocalPath>&& s) {
          paths.push_back({now(), s->plan_id, s->waypoints, map_, map_stamp_ns_});
        });
    create_subscription<msg::Maneuver>("maneuver", {.depth = 4}, [this](Sample<msg::Maneuver>&& s) {
      maneuvers.push_back({now(), s->kind, s->because_of_robot});
    });
    create_subscription<msg::RobotState>("robot_state", {.depth = 4},
                                         [this](Sample<msg::RobotState>&& s) {
                                           if (modes.empty() || modes.back().second != s->mode)
                                             modes.emplace_back(now(), s->mode);
                                         });
    return {};
  }
  double now() { return seconds(clock().now_ns()); }

  std::shared_ptr<const tsdf::MapSnapshot> map_;
  int64_t map_stamp_ns_ = 0;
};

// The robots' true poses (x, y, yaw) read from the simulator every 50 ms of sim time.
class PoseProbe final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: true robot poses every 50 ms";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  PoseProbe(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  struct Frame {
    double t_s = 0;
    std::vector<Eigen::Vector3d> poses;  // x, y, yaw per robot, in the launch file's order
  };
  const team_simulator::TeamSimulator* sim = nullptr;  // set by the test before the run
  std::vector<Frame> frames;

 private:
  Result<void, std::string> on_configure() override {
    create_timer(std::chrono::milliseconds(50), [this] {
      if (sim == nullptr || sim->simulator() == nullptr) return;
      const sim::TeamSim& s = *sim->simulator();
      Frame f;
      f.t_s = seconds(clock().now_ns());
      f.poses.reserve(s.robot_count());
      for (size_t i = 0; i < s.robot_count(); ++i) {
        const msg::Pose3 p = s.body_pose(i);
        const Eigen::Quaterniond q(p.orientation.w, p.orientation.x, p.orientation.y,
                                   p.orientation.z);
        const Eigen::Matrix3d r = q.toRotationMatrix();
        f.poses.emplace_back(p.position.x, p.position.y, std::atan2(r(1, 0), r(0, 0)));
      }
      frames.push_back(std::move(f));
    });
    return {};
  }
};

// --- geometry of the truth -------------------------------------------------------------

// A rectangle in the floor plane (every solid here stands on the floor and is taller than a
// ground robot, so contact is a question of footprints).
struct Rect {
  Eigen::Vector2d center;
  Eigen::Vector2d half;
  double yaw_rad = 0;
  std::array<Eigen::Vector2d, 4> corners() const {
    const Eigen::Rotation2Dd r(yaw_rad);
    return {center + r * Eigen::Vector2d(half.x(), half.y()),
            center + r * Eigen::Vector2d(-half.x(), half.y()),
            center + r * Eigen::Vector2d(-half.x(), -half.y()),
            center + r * Eigen::Vector2d(half.x(), -half.y())};
  }
};

// Separating axis test: the edges' normals of both rectangles.
bool overlap(const Rect& a, const Rect& b);

// The gap between two rectangles (0 when they overlap).
double gap(const Rect& a, const Rect& b);

// The ground robot's footprint (sim/robot_model.hpp: 0.44 x 0.40 m) at (x, y, yaw).
inline Rect footprint(const Eigen::Vector3d& pose) {
  return {.center = pose.head<2>(), .half = {0.22, 0.20}, .yaw_rad = pose.z()};
}

struct Truth {
  sim::SceneSpec scene;
  std::vector<Rect> solids;   // walls and boxes, footprints
  ObstacleGeometry geometry;  // walls and boxes, for the body test
};

Truth load_truth(const std::string& path);

// The smallest gap between the robot's footprint and any solid of the scene.
double scene_gap(const Truth& truth, const Eigen::Vector3d& pose);

// --- running a scenario ----------------------------------------------------------------

struct Pose4 {
  double x, y, z, yaw_deg;
};
struct RobotSetup {
  uint32_t id;
  Pose4 start;
  std::vector<Pose4> goals;
};

// tests/components/low_level_planner/scenes/<name>
std::string scene_path(const std::string& name);

// The scenarios' low-level parameters: these defaults, each unless `params` ("key: value, ...")
// sets it (a key twice in one mapping is an error).
std::string low_level_with_defaults(const std::string& params);

// low_level_params: more "key: value" pairs for the low-level planners (", "-separated)
std::string launch_text(const std::string& scene, const std::vector<RobotSetup>& robots,
                        double duration_s, const std::string& low_level_params);

struct Outcome {
  std::unique_ptr<Launch> launch;
  std::vector<const LowLevelPlanner*> planners;  // by robot, in the launch file's order
  std::vector<const path_tracker::PathTracker*> trackers;
  std::vector<const RobotLog*> logs;
  const PoseProbe* probe = nullptr;
  sim::ContactCounts contacts;
  double ran_s = 0;
};

// Runs until every robot has reached all its goals and its tracker is done (or the
// duration is over).
Outcome run_scenario(const std::string& scene, const std::vector<RobotSetup>& robots,
                     double duration_s, const std::string& low_level_params = "");

inline double distance_to(const Eigen::Vector3d& pose, const Pose4& goal) {
  return std::hypot(pose.x() - goal.x, pose.y() - goal.y);
}

// Both robots (all robots) reached every goal and ended at the last one within the
// tracker's tolerance; prints the times.
void expect_all_reached(const Outcome& o, const std::vector<RobotSetup>& robots, const char* name);

// Every local path against the true geometry, with the planner's body without its margin,
// every 2 cm. A path may only touch the truth where the map did not show free space at
// the time (unknown space planned as free with unknown_is_occupied: false, or the start
// of a back-off from a pose already too close): the number of paths that collide where
// the map showed free space is returned (each is also reported), and the number of paths
// that collide at all.
struct PathTally {
  size_t paths = 0, samples = 0, colliding = 0, colliding_in_known_free = 0;
};
PathTally check_paths(const Truth& truth, const Outcome& o);

// The robots' smallest centre-to-centre distance and footprint gap over the run, and when.
struct Separation {
  double centre_m = 1e300, gap_m = 1e300, t_s = 0;
};
Separation min_separation(const PoseProbe& probe);

// The pose of robot i at the first probe frame at or after t_s.
const Eigen::Vector3d* pose_at(const PoseProbe& probe, size_t i, double t_s);

inline bool is_traffic_hold(const RobotLog::Maneuver& m) {
  return m.because_of_robot != 0 &&
         (m.kind == ManeuverKind::kStop || m.kind == ManeuverKind::kStepAside);
}

// The two-robot scenarios' common checks: the robots never closer than two 0.3 m discs (the
// policy's bodies), and every local path clear of the scene's true geometry.
void expect_apart_and_clear_of_the_truth(const char* name, const std::string& scene,
                                         const Outcome& o);

}  // namespace scancrew::low_level_planner::scenario_harness
