#pragma once

// StallWatch: whether a robot sent along a local path has stopped getting anywhere on it.
// Not in the thesis, whose Algorithm 1 waits for GoalReached however long it takes: a robot
// that the tracker holds still on a path (its law at an equilibrium short of the goal, a
// controller fault on hardware), or that rocks to and fro on the spot, then waits for ever.
// In the parking lot (single robot, seed 5) one stood 1400 s "moving", 0.09 m beside its
// look-ahead point, until the mission's time ran out at 86.6 % coverage
// (docs/low_level_planner.md, "Stall watch"). The low-level planner plans again from where
// the robot stands when the watch fires, and skips the goal when it fires twice there.
//
// Progress is the way left along the path (remaining_length_m): the watch fires when it has
// not come min_progress_m below its least value since the watch (re)started for timeout_s.
// Motion that gets nowhere (turning on the spot, a swing back and forth) is no progress; a
// turn on the spot lasts seconds (π at the ground robot's 1 rad/s), well within the timeout.
// Pure; no allocation in update(); not thread safe.

#include <Eigen/Core>
#include <optional>
#include <span>

#include "interfaces/nav_msgs.hpp"

namespace scancrew::motion {

struct StallConfig {
  double timeout_s = 30.0;  // 0: never fires
  double min_progress_m = 0.1;
};

class StallWatch {
 public:
  explicit StallWatch(StallConfig config = {}) : config_(config) {}

  // Not on a path (a new path, a hold, a stop, a lost pose): the next update starts anew.
  void reset() { best_.reset(); }
  // The way left at `now_s`; true once per spell without progress, after timeout_s of it
  // (then the watch starts again from this value). A NaN is no progress.
  bool update(double remaining_m, double now_s);
  double stalled_for_s(double now_s) const { return best_ ? now_s - best_->at_s : 0.0; }

 private:
  struct Best {
    double remaining_m = 0;
    double at_s = 0;
  };
  StallConfig config_;
  std::optional<Best> best_;
};

// The length of `path` left from `position`: to the end of the segment nearest it
// (first_waypoint_ahead), then along the waypoints; in the plane when `planar` (a ground
// robot's goals carry the camera's height). 0 for an empty path.
double remaining_length_m(std::span<const msg::Waypoint> path, const Eigen::Vector3d& position,
                          bool planar);

}  // namespace scancrew::motion
