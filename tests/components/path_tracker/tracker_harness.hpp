#pragma once

// The path tracker tests' harness (test_path_tracker): a launch of the sim backend (test
// arena, sim time, bounded runs) with a path_player, the path_tracker and two test
// components, "test_tracker_log" (TrackerLog: keeps the ground-truth poses, the commands
// and the tracker states) and "test_tracker_injector" (maneuvers, empty paths, NaN and
// lost poses, as the traffic policy and a faulty planner or estimator would send them);
// and the geometry the tests check the runs with. The components are registered in
// tracker_harness.cpp, linked once into the test executable.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "components/path_tracker/path_tracker.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::path_tracker::testing {

// Keeps the ground-truth poses, the commands and the tracker states.
class TrackerLog final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: keeps pose_gt, cmd_vel, tracker_state";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  TrackerLog(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}
  std::vector<msg::Odometry> poses;
  std::vector<msg::VelocityCommand> commands;
  std::vector<msg::RobotState> states;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::Odometry>("pose_gt", {.depth = 8},
                                       [this](Sample<msg::Odometry>&& s) { poses.push_back(*s); });
    create_subscription<msg::VelocityCommand>(
        "cmd_vel", {.depth = 8},
        [this](Sample<msg::VelocityCommand>&& s) { commands.push_back(*s); });
    create_subscription<msg::RobotState>(
        "tracker_state", {.depth = 8},
        [this](Sample<msg::RobotState>&& s) { states.push_back(*s); });
    return {};
  }
};

struct Waypoint4 {
  double x, y, z, yaw_deg;
};

// The waypoints as a YAML flow list of quadruples.
std::string list(const std::vector<Waypoint4>& w);

// One robot of `kind` at `start` in the test arena for duration_s, with a path_player
// (params `player`), the path_tracker (params `tracker`, its pose port remapped to `pose`),
// the log and the injector (params `injector`).
std::string launch_text(const std::string& kind, const Waypoint4& start, double duration_s,
                        const std::string& player, const std::string& tracker,
                        const std::string& injector, const std::string& pose = "pose_gt");

struct TrackerRun {
  std::unique_ptr<Launch> launch;
  PathTracker* tracker = nullptr;
  TrackerLog* log = nullptr;
};

// Runs the launch file `text` to its end (a failure if it does not load: then empty).
TrackerRun run(const std::string& text);

double t_s(const msg::Header& h);
double distance(const msg::Odometry& o, const Waypoint4& w, bool planar);
double yaw_of(const msg::Odometry& o);
double yaw_error_deg(const msg::Odometry& o, const Waypoint4& w);

}  // namespace scancrew::path_tracker::testing
