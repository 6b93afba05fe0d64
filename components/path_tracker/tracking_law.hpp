#pragma once

// TrackingLaw: the path tracker's pose-based visual-servoing law (PBVS), computed with
// ViSP's vpServo. The robot's body frame plays the camera: the current frame c is the
// body, the desired frame c* is the target pose (the look-ahead pose on the local path,
// look_ahead.hpp). Features (Chaumette & Hutchinson 2006, "Visual servo control I", §V.A):
//   s = (c*t_c, θu(c*R_c)),  s* = 0,  L = [c*R_c  0; 0  L_θu]
//   v = −λ L⁺ (s − s*)   →   linear = λ · ct_c*   (a straight line to the target, body frame)
//                             angular ≈ −λ · θu    (the rotation to the target's attitude)
// with λ ViSP's adaptive gain λ(‖e‖∞) from gain_at_zero (λ(0)) to gain (λ(∞)), slope
// gain_slope at 0 (constant when gain_at_zero equals gain).
//
// Poses are reduced to x, y, z and yaw first (a level "heading frame"), so the twist comes
// out in that frame whatever roll and pitch the pose estimate has; roll and pitch rates
// are always zero. The twist is not limited here: velocity_mapping.hpp maps it to the
// robot's commands (unicycle or multirotor) and applies the speed limits.
//
// ViSP stays inside tracking_law.cpp (pimpl). Not thread safe (one tracker owns one law);
// compute() allocates (ViSP's matrices), a few hundred bytes per call.

#include <Eigen/Geometry>
#include <memory>

namespace scancrew::path_tracker {

struct TrackingLawConfig {
  double gain = 1.5;          // λ(∞), 1/s
  double gain_at_zero = 3.0;  // λ(0), 1/s; equal to gain: a constant gain
  double gain_slope = 15.0;   // λ'(0), the adaptive gain's slope at zero error
};

// A body-frame twist (the level heading frame of the body: x forward, y left, z up).
struct Twist {
  Eigen::Vector3d linear_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_radps = Eigen::Vector3d::Zero();
};

struct LawOutput {
  Twist twist;
  Eigen::Vector3d offset_body_m = Eigen::Vector3d::Zero();  // the target's position, body frame
  double yaw_error_rad = 0;  // target yaw − body yaw, in (−π, π]
  bool valid = true;         // false: ViSP failed (the twist is then zero)
};

class TrackingLaw {
 public:
  explicit TrackingLaw(TrackingLawConfig config = {});
  ~TrackingLaw();
  TrackingLaw(TrackingLaw&&) noexcept;
  TrackingLaw& operator=(TrackingLaw&&) noexcept;
  TrackingLaw(const TrackingLaw&) = delete;
  TrackingLaw& operator=(const TrackingLaw&) = delete;

  const TrackingLawConfig& config() const { return config_; }

  // The PBVS twist that drives T_world_body to T_world_target. Both must be finite
  // (the caller checks); only their yaw counts of the rotations.
  LawOutput compute(const Eigen::Isometry3d& T_world_body, const Eigen::Isometry3d& T_world_target);

 private:
  struct Impl;
  TrackingLawConfig config_;
  std::unique_ptr<Impl> impl_;
};

// The yaw of a rotation (rotation about world z of its x axis), and a level pose from
// x, y, z and yaw.
double yaw_of(const Eigen::Matrix3d& R_world_body);
Eigen::Isometry3d level_pose(const Eigen::Vector3d& position_m, double yaw_rad);

}  // namespace scancrew::path_tracker
