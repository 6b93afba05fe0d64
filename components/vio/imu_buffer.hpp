#pragma once

// ImuBuffer: the recent IMU samples of one robot, for the VIO's rotation prior between two
// frames (gyro integration) and the gravity direction at start (thesis 1.2.2: eVO aligns
// its first point cloud with the inertial vertical).
//
// Samples are body-frame specific force (m/s², reads +g up at rest) and angular rate
// (rad/s). Not thread safe: one component callback group uses it.

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>

namespace scancrew::vio {

class ImuBuffer {
 public:
  // max_gap_ns: the longest stretch without a sample that rotation() still bridges by
  // holding the nearest rate.
  explicit ImuBuffer(int64_t max_gap_ns = 100'000'000) : max_gap_ns_(max_gap_ns) {}

  // False (the sample is not kept) when its stamp is not after the last sample's.
  bool add(int64_t stamp_ns, const Eigen::Vector3d& accel_mps2, const Eigen::Vector3d& gyro_radps);

  // q_body0_body1: the rotation of the body at t1 expressed in the body frame at t0, from
  // the gyro held constant from each sample's stamp to the next. Nullopt when the samples
  // leave a gap longer than max_gap_ns in [t0, t1] (the IMU stopped or has not started).
  std::optional<Eigen::Quaterniond> rotation(int64_t t0_ns, int64_t t1_ns) const;

  // Mean specific force of the samples stamped in (t_ns - window_ns, t_ns]; nullopt if none.
  std::optional<Eigen::Vector3d> mean_accel(int64_t t_ns, int64_t window_ns) const;

  // Forgets what rotation() from t_ns on does not need.
  void drop_before(int64_t t_ns);

  size_t size() const { return samples_.size(); }

 private:
  struct Sample {
    int64_t stamp_ns;
    Eigen::Vector3d accel_mps2, gyro_radps;
  };
  int64_t max_gap_ns_;
  std::deque<Sample> samples_;
};

// The body's attitude whose +z axis is the measured "up" (the specific force at rest) and
// whose heading is yaw_rad: the start orientation of the VIO (roll and pitch from gravity,
// yaw from the launch file).
Eigen::Quaterniond gravity_aligned_attitude(const Eigen::Vector3d& accel_body_mps2, double yaw_rad);

}  // namespace scancrew::vio
