#pragma once

// Vio: the `vio` component, one per robot — stereo visual odometry with a gyro prior
// after eVO (thesis 1.2.2, 5.2.2; components/vio/stereo_odometry.hpp for the algorithm).
//
//   stereo     (StereoFrame) ─┐
//   imu        (Imu)         ─┼─► odom (Odometry: T_world_body at the frame's capture time)
//   wheel_odom (Odometry)    ─┘   ground robots with use_wheel_odom: the base's body-frame
//                                 velocity, the motion prior and coasting's translation
//
// World frame: the robot's start pose from the launch file's robots: entry (x, y, yaw;
// z for multirotors, 0 for ground robots whose body frame is on the floor), with roll and
// pitch from the accelerometer at the first frame. Robots of a team thus share one frame
// (the thesis assumes known initial poses).
//
// Input that cannot be used (empty or mismatched images, intrinsics that do not fit the
// image, NaN/inf IMU samples, stamps going back) is skipped, counted per reason and
// logged once per reason. A frame that fails to track is coasted through (the predicted
// pose, tracking_quality coast_quality) for up to max_coast_s; past that, lost tracking
// publishes one Odometry with tracking_quality 0 and tracking_resets incremented, logs the
// event, and re-initialises at the last pose; frames that cannot re-initialise (no texture)
// publish quality 0 until one can. pose_covariance: stereo_odometry.hpp, pose_covariance.hpp.
//
// Thread safety: both callbacks are in the component's (mutually exclusive) default group.
// stats() is for tests and the end-of-run log, read while the executor is not running.

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "components/vio/frame_check.hpp"
#include "components/vio/imu_buffer.hpp"
#include "components/vio/stereo_odometry.hpp"
#include "components/vio/wheel_buffer.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::vio {

struct VioStats {
  uint64_t frames = 0;          // stereo frames received
  uint64_t published = 0;       // odometry messages
  uint64_t imu_samples = 0;     // IMU samples received
  InputErrorCounts rejected{};  // per InputError, frames and IMU samples skipped
  uint32_t resets = 0;          // tracking losses (each followed by a re-initialisation)
  // the losses by LossReason (they sum to resets): which failure a mission meets decides
  // whether to coast through it or to change the tracking
  std::array<uint32_t, kLossReasonCount> losses{};
  uint64_t keyframes = 0;
  uint64_t untracked_frames = 0;  // published with quality 0 (the loss frames included)
  uint64_t coasted_frames = 0;    // published from the prediction (kCoasting), not losses
  double mean_frame_ms = 0, p50_frame_ms = 0, max_frame_ms = 0;  // processing time per frame

  uint64_t rejected_count(InputError e) const { return rejected[static_cast<size_t>(e)]; }
  uint32_t loss_count(LossReason r) const { return losses[static_cast<size_t>(r)]; }
};

class Vio final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "stereo visual odometry with a gyro prior (eVO-like): stereo + imu -> odom";
  struct Config {
    StereoOdometryConfig odometry;
    bool gravity_align = true;      // roll/pitch at start from the accelerometer
    double gravity_window_s = 0.5;  // accelerometer samples averaged for it, before frame 1
    double imu_max_gap_s = 0.1;     // longest IMU gap the gyro prior bridges
    uint32_t stereo_queue_depth = 2;
    uint32_t imu_queue_depth = 16;
    bool use_wheel_odom = false;  // a ground robot reads its base's `wheel_odom`
  };
  static Config read_config(ParamReader& p);

  Vio(ComponentContext context, Config config);
  ~Vio() override;

  void summarize(RunSummary& into) const override;  // its frames and losses
  VioStats stats() const;

 private:
  Result<void, std::string> on_configure() override;
  void on_deactivate() override;
  void on_imu(const msg::Imu& imu);
  void on_wheel_odom(const msg::Odometry& odom);
  void on_stereo(const msg::StereoFrame& frame);
  void reject(InputError error, int64_t stamp_ns);
  void start(const msg::StereoFrame& frame);
  void publish(const msg::StereoFrame& frame, const TrackingResult& result);
  void note_time(double ms);

  Config config_;
  std::unique_ptr<StereoOdometry> odometry_;
  ImuBuffer imu_;
  WheelBuffer wheels_;
  Publisher<msg::Odometry> odom_;
  // the launch file's start pose (position, yaw)
  Eigen::Vector3d start_position_m_ = Eigen::Vector3d::Zero();
  double start_yaw_rad_ = 0;
  int64_t last_frame_ns_ = msg::kStampUnset;  // the last frame processed
  Eigen::Isometry3d last_published_ = Eigen::Isometry3d::Identity();
  int64_t last_published_ns_ = msg::kStampUnset;
  bool lost_logged_ = false;
  VioStats stats_;
  double frame_ms_sum_ = 0;
  uint64_t timed_frames_ = 0;
  std::array<float, 1024> recent_frame_ms_{};  // ring of the last frame times (p50)
};

}  // namespace scancrew::vio
