#pragma once

// StallWatch: whether a robot sent along a local path has stood still too long. Not in the
// thesis, whose Algorithm 1 waits for GoalReached however long it takes: a robot that the
// tracker holds still on a path (its law at an equilibrium short of the goal, a controller
// fault on hardware) then waits for ever. In the parking lot (single robot, seed 5) one
// stood 1400 s "moving", 0.09 m beside its look-ahead point, until the mission's time ran
// out at 86.6 % coverage (docs/low_level_planner.md, "Stall watch"). The low-level planner
// plans again from where the robot stands when the watch fires, and skips the goal when it
// fires twice on it.
//
// Still: moved less than min_motion_m and turned less than min_turn_deg since the last
// motion (or reset); a turn on the spot is motion. Pure; no allocation; not thread safe.

#include <Eigen/Core>
#include <optional>

namespace scancrew::low_level {

struct StallConfig {
  double timeout_s = 30.0;  // 0: never fires
  double min_motion_m = 0.1;
  double min_turn_deg = 10.0;
};

class StallWatch {
 public:
  explicit StallWatch(StallConfig config = {}) : config_(config) {}

  // Not on a path (a new path, a hold, a stop): the next update starts a new watch.
  void reset() { since_.reset(); }
  // The robot's pose at `now_s` while it follows a path; true once per still spell, when it
  // has stood still for timeout_s (then the watch starts again from this pose).
  bool update(const Eigen::Vector3d& position, double yaw_rad, double now_s);
  double still_for_s(double now_s) const { return since_ ? now_s - since_->at_s : 0.0; }

 private:
  struct Since {
    Eigen::Vector3d position;
    double yaw_rad = 0;
    double at_s = 0;
  };
  StallConfig config_;
  std::optional<Since> since_;
};

}  // namespace scancrew::low_level
