#include "components/vio/stereo_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "components/vio/keyframe.hpp"

namespace scancrew::vio {

std::string_view to_string(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::kInitialised:
      return "initialised";
    case TrackingStatus::kTracked:
      return "tracked";
    case TrackingStatus::kNewKeyframe:
      return "new keyframe";
    case TrackingStatus::kCoasting:
      return "coasting";
    case TrackingStatus::kLost:
      return "lost";
    case TrackingStatus::kNotInitialised:
      return "not initialised";
  }
  return "unknown";
}

std::string_view to_string(LossReason reason) {
  switch (reason) {
    case LossReason::kNone:
      return "none";
    case LossReason::kTooFewTracks:
      return "too few tracked corners";
    case LossReason::kNoPoseSolution:
      return "PnP RANSAC found no pose";
    case LossReason::kTooFewInliers:
      return "too few PnP inliers";
    case LossReason::kGyroDisagreement:
      return "PnP rotation disagrees with the gyro";
    case LossReason::kCameraChanged:
      return "the image size changed";
  }
  return "unknown";
}

struct StereoOdometry::Impl {
  explicit Impl(const StereoOdometryConfig& c)
      : config(c), tracker(c.features), stereo(c.stereo), pose(c.pose) {}

  // Changes nothing but the tracker's previous image when the frame has fewer than
  // min_points stereo points (returns false); 0: min_keyframe_points.
  bool make_keyframe(const StereoInput& frame, const Eigen::Isometry3d& T_world_body,
                     uint32_t min_points = 0);
  void predict_pixels(const StereoInput& frame, const Eigen::Isometry3d& T_world_body_pred);
  // The complementary roll/pitch correction: turns T_world_body (and the keyframe with
  // it, about the body's position) toward the accelerometer's vertical.
  void correct_tilt(const Eigen::Vector3d& specific_force_mps2,
                    const Eigen::Isometry3d& T_prevbody_body, double dt_s,
                    Eigen::Isometry3d& T_world_body_now);
  // The body's motion since the last frame, as predicted for KLT's starting guess.
  Eigen::Isometry3d predict_motion(int64_t dt_ns, const ImuInterval& imu) const;
  // The coasted motion since the last frame: the gyro's rotation (else none) and the
  // wheels' velocity (else the smoothed body velocity) over dt.
  Eigen::Isometry3d coast_motion(int64_t dt_ns, const ImuInterval& imu) const;
  // Tracks the keyframe's points into this frame and solves its pose: kNone, else why not.
  LossReason track_pose(const StereoInput& frame, TrackingResult& result);
  // Takes a pose that passed the checks; a new keyframe when too few inliers are left.
  void accept(const StereoInput& frame, const Eigen::Isometry3d& T_prevbody_body_new,
              const Eigen::Isometry3d& T_world_new, int64_t dt_ns, TrackingResult& result);
  // A failed frame within max_coast_s of the last tracked one: publishes the prediction and
  // keeps the keyframe (or makes one at the prediction when too few tracks are left).
  void coast(const StereoInput& frame, LossReason why, const Eigen::Isometry3d& T_world_pred,
             TrackingResult& result);
  // A loss: a new keyframe at T_world_restart if the image allows one.
  void lose(const StereoInput& frame, LossReason why, const Eigen::Isometry3d& T_world_restart,
            TrackingResult& result);
  // Drops the keyframe and makes one from this frame at T_world_new if the image allows.
  void restart(const StereoInput& frame, const Eigen::Isometry3d& T_world_new,
               TrackingResult& result);
  // The covariance of the last tracked frame grown over the time since it (at the wheels'
  // velocity error when they drove the coasting).
  Covariance6 coasted_covariance(int64_t stamp_ns) const;

  StereoOdometryConfig config;
  FeatureTracker tracker;
  SparseStereo stereo;
  PoseEstimator pose;
  Keyframe keyframe;
  Tracks tracks;

  bool started = false, tracking = false;
  bool on_wheels = false;  // the current frame's interval has wheel odometry
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();  // latest estimate
  // constant-velocity model: the body motion between the last two tracked frames
  Eigen::Isometry3d T_prevbody_body = Eigen::Isometry3d::Identity();
  int64_t last_stamp_ns = 0, last_dt_ns = 0;
  bool have_stamp = false, have_motion = false;
  // body velocity averaged over about max_coast_s of tracked frames, from rest at a
  // (re)start (coasting's; one frame pair's motion is too noisy to hold for many frames)
  Eigen::Vector3d v_body_mps = Eigen::Vector3d::Zero();
  uint32_t resets = 0;
  uint64_t keyframes = 0, coasted = 0;
  // the last tracked (or initialised) frame: its stamp and covariance; the keyframe's
  int64_t last_good_ns = 0;
  bool have_good = false;
  Covariance6 cov_good = Covariance6::Identity(), cov_kf = Covariance6::Identity();

  // scratch, reused every frame
  std::vector<Eigen::Vector2f> corners, from;
  std::vector<uint8_t> ok;
  std::vector<Eigen::Vector3d> points;
  std::vector<StereoPoint> matched;
  PoseEstimate estimate;
};

bool StereoOdometry::Impl::make_keyframe(const StereoInput& frame,
                                         const Eigen::Isometry3d& T_world_body_kf,
                                         uint32_t min_points) {
  // the tracked inliers first (they are good corners), then fresh ones around them
  tracker.set_previous(frame.left);
  corners.assign(tracks.px.begin(), tracks.px.end());
  tracker.detect(tracks.px, corners);
  matched.clear();
  stereo.match(frame.left, frame.right, frame.intrinsics, frame.baseline_m, corners, matched);
  if (min_points == 0) min_points = config.min_keyframe_points;
  if (matched.size() < std::max<size_t>(min_points, 4)) return false;
  keyframe.id = ++keyframes;
  keyframe.stamp_ns = frame.stamp_ns;
  keyframe.T_world_cam = T_world_body_kf * frame.T_body_cam;
  keyframe.intrinsics = frame.intrinsics;
  keyframe.points_cam.clear();
  tracks.clear();
  for (const StereoPoint& s : matched) {
    tracks.point.push_back(static_cast<uint32_t>(keyframe.points_cam.size()));
    tracks.px.push_back(s.left_px);
    keyframe.points_cam.push_back(s.p_cam);
  }
  return true;
}

void StereoOdometry::Impl::predict_pixels(const StereoInput& frame,
                                          const Eigen::Isometry3d& T_world_body_pred) {
  // where each keyframe point lands under the predicted pose: KLT's starting guess
  const Eigen::Isometry3d T_cam_kf =
      (T_world_body_pred * frame.T_body_cam).inverse() * keyframe.T_world_cam;
  const msg::CameraIntrinsics& k = frame.intrinsics;
  const auto w = static_cast<float>(k.width), h = static_cast<float>(k.height);
  from.assign(tracks.px.begin(), tracks.px.end());
  for (size_t i = 0; i < tracks.size(); ++i) {
    const Eigen::Vector3d p = T_cam_kf * keyframe.points_cam[tracks.point[i]];
    if (p.z() < 0.05) continue;  // keeps the previous position
    const Eigen::Vector2f px(static_cast<float>(k.fx * p.x() / p.z() + k.cx),
                             static_cast<float>(k.fy * p.y() / p.z() + k.cy));
    if (px.x() >= 0 && px.y() >= 0 && px.x() < w && px.y() < h) tracks.px[i] = px;
  }
}

void StereoOdometry::Impl::correct_tilt(const Eigen::Vector3d& specific_force_mps2,
                                        const Eigen::Isometry3d& T_prevbody_body, double dt_s,
                                        Eigen::Isometry3d& T_world_body_now) {
  if (!(config.gravity_time_constant_s > 0)) return;
  constexpr double kGravity = 9.80665;
  // the specific force less its centripetal part ω×v leaves gravity (and the unmodelled
  // tangential acceleration, which the gate bounds)
  const Eigen::AngleAxisd turn(T_prevbody_body.rotation());
  const Eigen::Vector3d rate = turn.axis() * (turn.angle() / dt_s);
  const Eigen::Vector3d velocity = T_prevbody_body.translation() / dt_s;
  const Eigen::Vector3d up_body = specific_force_mps2 - rate.cross(velocity);
  if (std::abs(up_body.norm() - kGravity) > config.gravity_gate_mps2) return;
  const Eigen::Vector3d up_world = T_world_body_now.linear() * up_body.normalized();
  const Eigen::Vector3d axis = up_world.cross(Eigen::Vector3d::UnitZ());
  const double sin_angle = axis.norm();
  if (sin_angle < 1e-12) return;
  const double angle =
      std::atan2(sin_angle, up_world.z()) * std::min(1.0, dt_s / config.gravity_time_constant_s);
  // rotate the world about the body's position: the position stays, the tilt shrinks
  const Eigen::Vector3d p = T_world_body_now.translation();
  const Eigen::Isometry3d correction = Eigen::Translation3d(p) *
                                       Eigen::AngleAxisd(angle, axis / sin_angle) *
                                       Eigen::Translation3d(-p);
  T_world_body_now = correction * T_world_body_now;
  keyframe.T_world_cam = correction * keyframe.T_world_cam;
}

Eigen::Isometry3d StereoOdometry::Impl::predict_motion(int64_t dt_ns,
                                                       const ImuInterval& imu) const {
  // predicted pose: gyro rotation (or the last motion's), the wheels' translation (or the
  // last motion's: constant velocity)
  Eigen::Isometry3d T_prev_pred = Eigen::Isometry3d::Identity();
  if (have_motion && last_dt_ns > 0) {
    T_prev_pred = T_prevbody_body;
    T_prev_pred.translation() *= static_cast<double>(dt_ns) / static_cast<double>(last_dt_ns);
  }
  const std::optional<Eigen::Quaterniond> gyro =
      config.gyro_prior ? imu.q_prevbody_body : std::nullopt;
  if (gyro) T_prev_pred.linear() = gyro->toRotationMatrix();
  if (imu.wheel_velocity_mps)
    T_prev_pred.translation() = *imu.wheel_velocity_mps * (static_cast<double>(dt_ns) * 1e-9);
  return T_prev_pred;
}

Eigen::Isometry3d StereoOdometry::Impl::coast_motion(int64_t dt_ns, const ImuInterval& imu) const {
  Eigen::Isometry3d T_prev_pred = Eigen::Isometry3d::Identity();
  const double dt_s = static_cast<double>(dt_ns) * 1e-9;
  if (imu.wheel_velocity_mps)
    T_prev_pred.translation() = *imu.wheel_velocity_mps * dt_s;
  else if (have_motion)
    T_prev_pred.translation() = v_body_mps * dt_s;
  const std::optional<Eigen::Quaterniond> gyro =
      config.gyro_prior ? imu.q_prevbody_body : std::nullopt;
  if (gyro) T_prev_pred.linear() = gyro->toRotationMatrix();
  return T_prev_pred;
}

LossReason StereoOdometry::Impl::track_pose(const StereoInput& frame, TrackingResult& result) {
  // KLT from the previous image, then the pose against the keyframe
  tracker.track(frame.left, from, tracks.px, ok);
  tracks.keep_if(ok);
  result.tracked = tracks.size();
  result.keyframe_points = keyframe.points_cam.size();
  if (tracks.size() < std::max<size_t>(config.pose.min_inliers, 4))
    return LossReason::kTooFewTracks;
  points.clear();
  for (const uint32_t i : tracks.point) points.push_back(keyframe.points_cam[i]);
  pose.estimate(points, tracks.px, frame.intrinsics, estimate);
  if (estimate.status == PoseStatus::kTooFewInliers) return LossReason::kTooFewInliers;
  if (estimate.status != PoseStatus::kOk) return LossReason::kNoPoseSolution;
  return LossReason::kNone;
}

void StereoOdometry::Impl::accept(const StereoInput& frame,
                                  const Eigen::Isometry3d& T_prevbody_body_new,
                                  const Eigen::Isometry3d& T_world_new, int64_t dt_ns,
                                  TrackingResult& result) {
  // accepted: keep the inliers, update the motion model and the covariance
  tracks.keep_if(estimate.inlier);
  result.covariance = compose(keyframe.T_world_cam, cov_kf, estimate.T_cam_ref.inverse(),
                              camera_in_reference(estimate.T_cam_ref, estimate.covariance_rt));
  cov_good = result.covariance;
  last_good_ns = frame.stamp_ns;
  have_good = true;
  result.inliers = estimate.inliers;
  result.quality = static_cast<double>(estimate.inliers) / static_cast<double>(result.tracked);
  T_prevbody_body = T_prevbody_body_new;
  last_dt_ns = dt_ns;
  if (dt_ns > 0) {
    const double dt_s = static_cast<double>(dt_ns) * 1e-9;
    const Eigen::Vector3d v = T_prevbody_body_new.translation() / dt_s;
    // from rest after a (re)start: a stopped robot is the safer guess
    const double a = dt_s / (std::max(config.max_coast_s, dt_s) + dt_s);
    v_body_mps += a * (v - v_body_mps);
  }
  have_motion = dt_ns > 0;
  T_world_body = T_world_new;
  result.T_world_body = T_world_new;
  result.status = TrackingStatus::kTracked;
  const auto needed =
      std::max(static_cast<double>(config.keyframe_min_inliers),
               config.keyframe_min_inlier_ratio * static_cast<double>(keyframe.points_cam.size()));
  if (static_cast<double>(estimate.inliers) < needed) {
    // make_keyframe() changes nothing when it fails: the old keyframe stays tracked
    if (make_keyframe(frame, T_world_new)) {
      cov_kf = result.covariance;
      result.status = TrackingStatus::kNewKeyframe;
      result.keyframe_points = keyframe.points_cam.size();
    }
  }
}

Covariance6 StereoOdometry::Impl::coasted_covariance(int64_t stamp_ns) const {
  if (!have_good) return cov_good;
  const double coast_s = static_cast<double>(stamp_ns - last_good_ns) * 1e-9;
  const double velocity_sigma =
      on_wheels ? config.coast_wheel_sigma_mps : config.coast_velocity_sigma_mps;
  return cov_good + coast_growth(coast_s, velocity_sigma, config.coast_gyro_sigma_radps);
}

void StereoOdometry::Impl::coast(const StereoInput& frame, LossReason why,
                                 const Eigen::Isometry3d& T_world_pred, TrackingResult& result) {
  // the prediction stands in for the pose; the motion model and the keyframe stay, so the
  // next frame is predicted at the same velocity and tried against the same keyframe
  ++coasted;
  T_world_body = T_world_pred;
  result.status = TrackingStatus::kCoasting;
  result.loss = why;
  result.T_world_body = T_world_pred;
  result.quality = config.coast_quality;
  result.covariance = coasted_covariance(frame.stamp_ns);
  // too few tracks to try again: a keyframe at the prediction, if this image makes one
  if (why == LossReason::kTooFewTracks &&
      make_keyframe(frame, T_world_pred, config.rescue_keyframe_min_points)) {
    cov_kf = result.covariance;
    result.keyframe_points = keyframe.points_cam.size();
  }
}

void StereoOdometry::Impl::restart(const StereoInput& frame, const Eigen::Isometry3d& T_world_new,
                                   TrackingResult& result) {
  T_world_body = T_world_new;
  tracks.clear();
  have_motion = false;
  v_body_mps.setZero();
  result.covariance = coasted_covariance(frame.stamp_ns);
  tracking = make_keyframe(frame, T_world_new);
  result.keyframe_points = tracking ? keyframe.points_cam.size() : 0;
  result.T_world_body = T_world_new;
  if (!tracking) return;
  cov_kf = cov_good = result.covariance;
  last_good_ns = frame.stamp_ns;
  have_good = true;
}

void StereoOdometry::Impl::lose(const StereoInput& frame, LossReason why,
                                const Eigen::Isometry3d& T_world_restart, TrackingResult& result) {
  ++resets;
  result.loss = why;
  // a new keyframe at once if this image allows it, else at a later frame
  restart(frame, T_world_restart, result);
  result.status = TrackingStatus::kLost;
  result.quality = 0;
}

StereoOdometry::StereoOdometry(const StereoOdometryConfig& config)
    : impl_(std::make_unique<Impl>(config)) {}

StereoOdometry::~StereoOdometry() = default;

void StereoOdometry::set_start(const Eigen::Isometry3d& T_world_body) {
  Impl& m = *impl_;
  m.started = true;
  m.tracking = false;
  m.T_world_body = T_world_body;
  m.have_motion = false;
  m.have_stamp = false;
  m.v_body_mps.setZero();
  m.tracks.clear();
  const StereoOdometryConfig& c = m.config;
  m.cov_good.setZero();
  m.cov_good.diagonal() << Eigen::Vector3d::Constant(c.start_sigma_m * c.start_sigma_m),
      Eigen::Vector3d::Constant(c.start_sigma_rad * c.start_sigma_rad);
  m.cov_kf = m.cov_good;
  m.have_good = false;
}

bool StereoOdometry::started() const {
  return impl_->started;
}
uint32_t StereoOdometry::resets() const {
  return impl_->resets;
}
uint64_t StereoOdometry::keyframes() const {
  return impl_->keyframes;
}
uint64_t StereoOdometry::coasted_frames() const {
  return impl_->coasted;
}

TrackingResult StereoOdometry::process(const StereoInput& frame, const ImuInterval& imu) {
  Impl& m = *impl_;
  const StereoOdometryConfig& c = m.config;
  m.started = true;
  TrackingResult result;
  const std::optional<Eigen::Quaterniond> gyro = c.gyro_prior ? imu.q_prevbody_body : std::nullopt;
  const int64_t dt_ns = m.have_stamp ? frame.stamp_ns - m.last_stamp_ns : 0;
  m.last_stamp_ns = frame.stamp_ns;
  m.have_stamp = true;
  const Eigen::Isometry3d T_world_last = m.T_world_body;
  m.on_wheels = imu.wheel_velocity_mps.has_value();

  // the last pose turned by the gyro (and moved by the wheels): where a lost or
  // re-initialised robot is assumed
  Eigen::Isometry3d T_world_turned = T_world_last;
  if (gyro) T_world_turned.linear() = T_world_last.linear() * gyro->toRotationMatrix();
  if (imu.wheel_velocity_mps && dt_ns > 0)
    T_world_turned.translation() +=
        T_world_last.linear() * (*imu.wheel_velocity_mps * (static_cast<double>(dt_ns) * 1e-9));

  if (!m.tracking) {
    m.restart(frame, T_world_turned, result);
    result.status = m.tracking ? TrackingStatus::kInitialised : TrackingStatus::kNotInitialised;
    result.quality = m.tracking ? 1.0 : 0.0;
    return result;
  }
  if (frame.intrinsics.width != m.keyframe.intrinsics.width ||
      frame.intrinsics.height != m.keyframe.intrinsics.height) {
    m.lose(frame, LossReason::kCameraChanged, T_world_turned, result);
    return result;
  }

  const Eigen::Isometry3d T_world_pred = T_world_last * m.predict_motion(dt_ns, imu);
  m.predict_pixels(frame, T_world_pred);
  LossReason failure = m.track_pose(frame, result);
  Eigen::Isometry3d T_world_new = T_world_pred;
  Eigen::Isometry3d T_prevbody_body = Eigen::Isometry3d::Identity();
  if (failure == LossReason::kNone) {
    const Eigen::Isometry3d T_world_cam = m.keyframe.T_world_cam * m.estimate.T_cam_ref.inverse();
    T_world_new = T_world_cam * frame.T_body_cam.inverse();
    T_prevbody_body = T_world_last.inverse() * T_world_new;
    if (gyro && Eigen::Quaterniond(T_prevbody_body.rotation()).angularDistance(*gyro) >
                    c.max_gyro_disagreement_deg * M_PI / 180.0)
      failure = LossReason::kGyroDisagreement;
  }
  if (failure != LossReason::kNone) {
    // coast while the last tracked frame is recent enough, else a loss
    const double max_coast_s = m.on_wheels ? c.max_wheel_coast_s : c.max_coast_s;
    const auto max_coast_ns = static_cast<int64_t>(max_coast_s * 1e9);
    if (frame.stamp_ns - m.last_good_ns > max_coast_ns)
      m.lose(frame, failure, T_world_turned, result);
    else
      m.coast(frame, failure, T_world_last * m.coast_motion(dt_ns, imu), result);
    return result;
  }

  if (imu.mean_specific_force_mps2 && dt_ns > 0)
    m.correct_tilt(*imu.mean_specific_force_mps2, T_prevbody_body,
                   static_cast<double>(dt_ns) * 1e-9, T_world_new);

  m.accept(frame, T_prevbody_body, T_world_new, dt_ns, result);
  return result;
}

}  // namespace scancrew::vio
