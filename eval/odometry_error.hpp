#pragma once

// Odometry error against ground truth, the figures used for visual odometry
// (Sturm et al., "A benchmark for the evaluation of RGB-D SLAM systems", IROS 2012 for ATE;
// Geiger et al., "Are we ready for autonomous driving? The KITTI vision benchmark
// suite", CVPR 2012 for the drift in % of the distance travelled).
//
//   ATE: RMSE of the position error of the estimate against the ground truth of the same
//        stamp, optionally after aligning the estimate (off by default: the start pose is
//        known, thesis 3.2, so an odometry is scored in the shared world frame).
//   RPE: for every start pose i (ground truth), the first pose j at least L metres of path
//        later; the error of the estimated relative motion T_i⁻¹T_j against the true one,
//        translational part / L, in %; mean, RMSE and max over all such segments.
//
// Plain functions on plain data; allocate their working copies; thread safe.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/result.hpp"
#include "interfaces/geometry.hpp"

namespace scancrew::eval {

struct StampedPose {
  int64_t stamp_ns = 0;
  msg::Pose3 pose;  // T_world_body
};

enum class Alignment : uint8_t {
  kNone,  // compare in the shared world frame (the default)
  kSe3,   // rotation + translation minimising the position error (Umeyama, no scale)
  kYaw,   // rotation about z + translation (4 DoF: gravity is observable)
};
std::string_view to_string(Alignment alignment);

struct OdometryErrorConfig {
  Alignment alignment = Alignment::kNone;
  double segment_length_m = 1.0;        // RPE segment length L, > 0
  int64_t max_stamp_difference_ns = 0;  // estimate and ground truth match within this
};

struct OdometryError {
  size_t matched = 0;     // estimate poses with a ground-truth pose of the same stamp
  double distance_m = 0;  // path length of the matched ground truth
  double ate_rmse_m = 0;  // absolute trajectory error
  double ate_max_m = 0;
  size_t segments = 0;  // RPE segments of length >= L (0 if the path is shorter)
  double rpe_mean_percent = 0;
  double rpe_rmse_percent = 0;
  double rpe_max_percent = 0;
  double rpe_rotation_deg_per_m = 0;  // mean rotational drift over the segments
};

// Both trajectories in any stamp order (they are sorted by stamp here). Fails when no
// stamp matches, a pose is not finite, or the configuration is invalid.
Result<OdometryError, std::string> odometry_error(const std::vector<StampedPose>& estimate,
                                                  const std::vector<StampedPose>& ground_truth,
                                                  const OdometryErrorConfig& config = {});

}  // namespace scancrew::eval
