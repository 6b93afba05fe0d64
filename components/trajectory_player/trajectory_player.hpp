#pragma once

// TrajectoryPlayer: takes a robot along the path a mission recorded (a run directory's
// paths.csv, this robot's rows), in time, through the path tracker: at each recorded sample
// it sends a one-waypoint LocalPath to the pose recorded lead_s later (a new plan each
// time). With the same scene and sensors, a run of it reproduces a mission's views without
// its planners, so mapping parameters can be compared on the same trajectories
// (launch_cfg/experiments/powerplant_replay.yaml; docs/missions.md, "Replaying a mission's
// paths"). Not a planner: no collision check; the poses are those the robot flew.
//
// Parameters
//   paths_csv  the run's paths.csv (t_s, robot_id, x_m, y_m, z_m, yaw_rad); required. The
//              file is read when the component is configured: a missing file, a bad line,
//              no row for this robot or times that do not increase are refused, with why.
//   lead_s     the target is the pose recorded this long after now (default 0.5, the
//              recording's period); after the last sample, the last pose
// Port: out local_path (msg::LocalPath). Per robot (per_robot: true).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::trajectory_player {

class TrajectoryPlayer final : public Component {
 public:
  // not on a robot or the station: never charged compute (StepExecutor)
  static constexpr bool kWorld = true;
  static constexpr std::string_view kDescription =
      "takes the robot along a recorded mission's paths.csv in time, through the tracker";
  struct Config {
    std::string paths_csv;
    double lead_s = 0.5;
  };
  static Config read_config(ParamReader& p);

  TrajectoryPlayer(ComponentContext context, Config config);

  size_t samples() const { return times_s_.size(); }
  uint32_t sent() const { return sent_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_tick();

  Config config_;
  std::vector<double> times_s_;           // this robot's sample times, increasing
  std::vector<msg::Waypoint> waypoints_;  // its poses
  Publisher<msg::LocalPath> path_;
  size_t target_ = SIZE_MAX;  // the sample last sent
  uint32_t sent_ = 0;
};

}  // namespace scancrew::trajectory_player
