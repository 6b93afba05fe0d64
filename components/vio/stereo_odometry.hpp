#pragma once

// StereoOdometry: keyframe-based stereo visual odometry with a gyro prior, after eVO
// (Sanfourche, Vittori & Le Besnerais, "eVO: a realtime embedded stereo odometry for MAV
// applications", IROS 2013; thesis 1.2.2, 5.2.2).
//
//   keyframe:  corners on the left image (grid-bucketed Shi-Tomasi), matched along the row
//              in the right image and triangulated, z = f·B/d (A.2.2)
//   each frame: KLT from the previous image, each track starting where the predicted pose
//              (gyro rotation, constant-velocity translation) projects its keyframe point;
//              P3P-RANSAC + LM refinement gives T_cam_keyframe; outliers are dropped
//   gravity:   the keyframe's roll and pitch are pulled toward the accelerometer's vertical
//              (eVO aligns its point clouds with the inertial vertical), so tilt drift
//              does not build up from keyframe to keyframe
//   new keyframe: when the inliers fall below keyframe_min_inliers (or a share of the
//              keyframe's points); the tracked inliers are kept as corners of the new one
//   coasting:  a frame that fails (too few tracks, no PnP solution, too few inliers, a PnP
//              rotation that disagrees with the gyro) publishes the prediction (gyro rotation,
//              constant-velocity translation) with quality coast_quality and keeps the
//              keyframe: the next frame tries it again. With too few tracks left to retry,
//              a new keyframe is made at the predicted pose when the image allows one
//              (rescue_keyframe_min_points, fewer than a keyframe otherwise needs).
//   lost:      still failing max_coast_s after the last tracked frame, or a new image size:
//              the frame is reported lost (quality 0) and a new keyframe is made at the last
//              (predicted) pose turned by the gyro; if the image cannot make one (black,
//              textureless), each later frame tries again.
//   wheels:    a ground robot's wheel odometry (ImuInterval::wheel_velocity_mps), when
//              given, replaces the constant-velocity translation in the prediction, the
//              coasting and a lost robot's pose, and lets it coast max_wheel_coast_s
//              (gyro rotation + wheel translation: dead reckoning through images without
//              corners, as a real ground robot's odometry does).
//   covariance: each frame's pose covariance (pose_covariance.hpp): the PnP estimate's on
//              top of the keyframe's, accumulated across keyframes, grown while coasting.
//
// A plain library (no runtime): the `vio` component feeds it checked frames. OpenCV stays
// in the .cpp files. Not thread safe. Its own buffers keep their capacity; OpenCV
// allocates scratch inside KLT and RANSAC calls.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

#include "components/vio/feature_tracker.hpp"
#include "components/vio/gray_image.hpp"
#include "components/vio/pose_covariance.hpp"
#include "components/vio/pose_estimator.hpp"
#include "components/vio/sparse_stereo.hpp"
#include "interfaces/geometry.hpp"

namespace scancrew::vio {

struct StereoOdometryConfig {
  FeatureTrackerConfig features;
  SparseStereoConfig stereo;
  PoseEstimatorConfig pose;
  uint32_t keyframe_min_inliers = 80;      // fewer PnP inliers: the frame becomes a keyframe
  double keyframe_min_inlier_ratio = 0.6;  // or fewer than this share of the keyframe's points
  uint32_t min_keyframe_points = 25;       // a keyframe needs this many triangulated corners
  // or this many when made while coasting with too few tracks left (a weak keyframe rather
  // than a loss: near or plain faces leave few corners)
  uint32_t rescue_keyframe_min_points = 15;
  bool gyro_prior = true;                  // rotation prior from the gyro (else constant velocity)
  double max_gyro_disagreement_deg = 5.0;  // PnP vs gyro rotation since the last frame
  // roll and pitch pulled toward the accelerometer's vertical with this time constant
  // (a complementary filter; 0: off), using intervals whose specific force, less the
  // centripetal part ω×v, is within gravity_gate_mps2 of g
  double gravity_time_constant_s = 2.0;
  double gravity_gate_mps2 = 0.3;
  // coasting through failed frames (0: every failed frame is a loss)
  double max_coast_s = 0.5;               // a failure this long after the last tracked frame: lost
  double coast_quality = 0.5;             // tracking quality published while coasting, (0, 1]
  double coast_velocity_sigma_mps = 0.2;  // constant-velocity error, for the covariance
  double coast_gyro_sigma_radps = 0.01;   // gyro rate error, for the covariance
  // with wheel odometry: how long a failure coasts before it is a loss, and the wheel
  // velocity's error for the covariance (a 2 % scale error at 0.5 m/s, plus noise)
  double max_wheel_coast_s = 5.0;
  double coast_wheel_sigma_mps = 0.02;
  double start_sigma_m = 0.001, start_sigma_rad = 0.001;  // the start pose's uncertainty
};

// What the IMU says about the interval since the previous frame (body frame).
struct ImuInterval {
  std::optional<Eigen::Quaterniond> q_prevbody_body;        // gyro rotation (nullopt: no IMU)
  std::optional<Eigen::Vector3d> mean_specific_force_mps2;  // accelerometer mean
  // the wheels' mean body-frame velocity over the interval (nullopt: no wheel odometry)
  std::optional<Eigen::Vector3d> wheel_velocity_mps;
};

// A checked stereo frame (frame_check.hpp): images of the intrinsics' size.
struct StereoInput {
  GrayImage left, right;
  msg::CameraIntrinsics intrinsics;
  double baseline_m = 0;
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  int64_t stamp_ns = 0;
};

enum class TrackingStatus : uint8_t {
  kInitialised,     // first keyframe (or the one after a loss) made from this frame
  kTracked,         // pose from the current keyframe
  kNewKeyframe,     // tracked, and this frame became the new keyframe
  kCoasting,        // not tracked at this frame: the predicted pose, quality coast_quality
  kLost,            // tracking lost at this frame (a reset); pose is the last good one
  kNotInitialised,  // no keyframe could be made yet (too few stereo points)
};
std::string_view to_string(TrackingStatus status);

enum class LossReason : uint8_t {
  kNone,
  kTooFewTracks,
  kNoPoseSolution,
  kTooFewInliers,
  kGyroDisagreement,
  kCameraChanged,  // the image size changed
};
inline constexpr size_t kLossReasonCount = 6;
static_assert(static_cast<size_t>(LossReason::kCameraChanged) + 1 == kLossReasonCount);
std::string_view to_string(LossReason reason);

struct TrackingResult {
  TrackingStatus status = TrackingStatus::kNotInitialised;
  // kLost: why; kCoasting: why this frame failed (not a loss)
  LossReason loss = LossReason::kNone;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  // position (m², world axes) then rotation (rad², small world-frame angles); see
  // pose_covariance.hpp
  Covariance6 covariance = Covariance6::Identity();
  double quality = 0;  // PnP inliers / tracks; 1 at a fresh keyframe; 0 when lost
  size_t tracked = 0, inliers = 0, keyframe_points = 0;
};

class StereoOdometry {
 public:
  explicit StereoOdometry(const StereoOdometryConfig& config);
  ~StereoOdometry();
  StereoOdometry(const StereoOdometry&) = delete;
  StereoOdometry& operator=(const StereoOdometry&) = delete;

  // The body pose at the first frame (the launch's start pose, gravity-aligned).
  // Forgets any keyframe.
  void set_start(const Eigen::Isometry3d& T_world_body);
  bool started() const;

  TrackingResult process(const StereoInput& frame, const ImuInterval& imu);

  uint32_t resets() const;          // losses so far
  uint64_t keyframes() const;       // keyframes made so far
  uint64_t coasted_frames() const;  // frames published as kCoasting so far

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::vio
