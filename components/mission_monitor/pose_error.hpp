#pragma once

// PoseError: how far the pose the robots run on (an odometry: the launch's `pose` remapped to
// `odom`) is from the simulator's truth, per robot and between robots.
//
//   Per robot: the estimate's poses matched by stamp with the truth's (the simulator publishes
//   pose_gt at each camera frame, with the frame's stamp, and the odometry stamps its pose
//   with the image's), scored by eval::odometry_error in the shared world frame (no
//   alignment: the start poses are known, thesis 5.2): ATE, its share of the distance
//   travelled, RPE over 1 m segments.
//   Between robots: the frame error of robot i is E_i = T_est,i · T_true,i⁻¹, the transform
//   that carries a true world point to where robot i's map puts it. Two robots disagree about
//   a point p by |E_i p − E_j p|: a surface both see is mapped twice that far apart. It is
//   sampled at the midpoint of their true positions, at every sample() call where both have
//   a matched pose of the last second.
//
// Not thread safe: the monitor calls it under its mutex.

#include <cstdint>
#include <optional>
#include <vector>

#include "eval/odometry_error.hpp"
#include "interfaces/nav_msgs.hpp"

namespace scancrew::mission_monitor {

class PoseError {
 public:
  explicit PoseError(size_t robots);

  void on_truth(size_t robot, const msg::Odometry& truth);
  void on_estimate(size_t robot, const msg::Odometry& estimate);
  // One sample of the pairwise disagreement, at time now_ns of the launch's clock.
  void sample(int64_t now_ns);

  struct Pair {
    size_t a = 0, b = 0;  // robot indices, a < b
    size_t samples = 0;
    double mean_m = 0, max_m = 0, last_m = 0;
    double max_yaw_deg = 0;  // the largest difference of the two frames' yaw errors
  };
  std::vector<Pair> pairs() const;
  // nullopt: no estimate matched a true pose yet
  std::optional<eval::OdometryError> robot_error(size_t robot) const;
  size_t matched(size_t robot) const { return robots_[robot].estimate.size(); }

 private:
  struct Robot {
    std::vector<eval::StampedPose> truth_recent;     // unmatched truth, oldest first
    std::vector<eval::StampedPose> estimate, truth;  // matched pairs, same stamps
  };
  std::vector<Robot> robots_;
  std::vector<Pair> pairs_;
  std::vector<double> sums_;  // of each pair's samples, for the mean
};

}  // namespace scancrew::mission_monitor
