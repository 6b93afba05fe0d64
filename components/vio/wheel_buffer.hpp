#pragma once

// WheelBuffer: the recent wheel-odometry readings of one ground robot (its base's body-frame
// velocity, `wheel_odom`), for the VIO's motion prior between two frames: where KLT starts
// each corner, and the translation it coasts on through images without corners
// (stereo_odometry.hpp). Not thread safe: one component callback group uses it.

#include <Eigen/Core>
#include <cstdint>
#include <deque>
#include <optional>

namespace scancrew::vio {

class WheelBuffer {
 public:
  // max_gap_ns: a reading older than this before the interval's end is too old to use.
  explicit WheelBuffer(int64_t max_gap_ns = 200'000'000) : max_gap_ns_(max_gap_ns) {}

  // False (the reading is not kept) when its stamp is not after the last one's.
  bool add(int64_t stamp_ns, const Eigen::Vector3d& velocity_body_mps);

  // The mean body-frame velocity over [t0, t1]: each reading held from its stamp to the
  // next. Nullopt when no reading is at or before t0 + max_gap or the last is more than
  // max_gap before t1 (the base stopped reporting).
  std::optional<Eigen::Vector3d> mean_velocity(int64_t t0_ns, int64_t t1_ns) const;

  // Forgets the readings mean_velocity() from t_ns on does not need.
  void drop_before(int64_t t_ns);

  size_t size() const { return readings_.size(); }

 private:
  struct Reading {
    int64_t stamp_ns;
    Eigen::Vector3d velocity_mps;
  };
  int64_t max_gap_ns_;
  std::deque<Reading> readings_;
};

}  // namespace scancrew::vio
