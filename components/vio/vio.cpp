#include "components/vio/vio.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "executors/log.hpp"
#include "executors/registry.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::vio {

namespace {

// The corners, KLT, stereo matching and PnP keys of read_config().
void read_tracking(ParamReader& p, StereoOdometryConfig& o) {
  // corners and KLT
  p.optional("max_features", o.features.max_features, {8, 5000})
      .doc("corners per keyframe, kept tracks included");
  p.optional("grid_cols", o.features.grid_cols, {1, 64})
      .doc("detection buckets: columns (at most max_features/cells corners per cell first)");
  p.optional("grid_rows", o.features.grid_rows, {1, 64}).doc("detection buckets: rows");
  p.optional("corner_quality", o.features.quality_level, {1e-5, 0.5})
      .doc("Shi-Tomasi threshold, relative to the strongest corner");
  p.optional("min_corner_distance_px", o.features.min_distance_px, {1, 100})
      .doc("between corners and from kept tracks (px)");
  p.optional("border_px", o.features.border_px, {0, 100})
      .doc("no corner nearer the image border (px)");
  p.optional("klt_window_px", o.features.klt_window_px, {5, 61}).doc("KLT window (odd, px)");
  p.optional("klt_levels", o.features.klt_levels, {0, 6})
      .doc("KLT pyramid levels above full resolution");
  p.optional("klt_iterations", o.features.klt_iterations, {1, 200}).doc("KLT iterations per level");
  p.optional("klt_max_error", o.features.klt_max_error, {0.1, 255})
      .doc("KLT: mean absolute patch difference accepted (grey levels)");
  if (o.features.klt_window_px % 2 == 0) p.report("klt_window_px", "must be odd");
  // stereo matching
  p.optional("stereo_window_px", o.stereo.window_px, {3, 31}).doc("stereo block width (odd, px)");
  p.optional("stereo_window_rows", o.stereo.window_rows, {1, 31})
      .doc("stereo block height (odd, px)");
  p.optional("min_depth_m", o.stereo.min_depth_m, {0.01, 100})
      .doc("nearest depth triangulated (m; disparity search range)");
  p.optional("max_depth_m", o.stereo.max_depth_m, {0.02, 1000})
      .doc("farthest depth triangulated (m)");
  p.optional("stereo_uniqueness_ratio", o.stereo.uniqueness_ratio, {0.1, 1.0})
      .doc("best SSD < ratio × best SSD more than 2 px away");
  p.optional("stereo_klt_refine", o.stereo.klt_refine).doc("sub-pixel disparity by KLT left→right");
  p.optional("stereo_max_row_error_px", o.stereo.max_row_error_px, {0.05, 5})
      .doc("KLT refinement must stay this close to the row (px)");
  if (o.stereo.window_px % 2 == 0) p.report("stereo_window_px", "must be odd");
  if (o.stereo.window_rows % 2 == 0) p.report("stereo_window_rows", "must be odd");
  if (o.stereo.min_depth_m >= o.stereo.max_depth_m)
    p.report("max_depth_m", "must be greater than min_depth_m");
  // pose
  p.optional("ransac_reprojection_px", o.pose.ransac_reprojection_px, {0.1, 20})
      .doc("PnP inlier threshold (px)");
  p.optional("ransac_iterations", o.pose.ransac_iterations, {1, 10000})
      .doc("PnP RANSAC iterations");
  p.optional("ransac_confidence", o.pose.ransac_confidence, {0.5, 0.99999})
      .doc("PnP RANSAC confidence");
  p.choice("pnp_solver", o.pose.solver, kPnpSolverNames).doc("minimal solver inside RANSAC");
  p.optional("pnp_refine", o.pose.refine).doc("LM refinement on the inliers");
  p.optional("min_inliers", o.pose.min_inliers, {4, 1000}).doc("fewer PnP inliers: tracking lost");
}

}  // namespace

Vio::Config Vio::read_config(ParamReader& p) {
  Config c;
  StereoOdometryConfig& o = c.odometry;
  read_tracking(p, o);
  // keyframes and priors
  p.optional("keyframe_min_inliers", o.keyframe_min_inliers, {4, 5000})
      .doc("fewer inliers: new keyframe (≥ min_inliers)");
  p.optional("keyframe_min_inlier_ratio", o.keyframe_min_inlier_ratio, {0, 1})
      .doc("or fewer than this share of the keyframe's points");
  p.optional("min_keyframe_points", o.min_keyframe_points, {4, 5000})
      .doc("a keyframe needs this many triangulated corners");
  p.optional("rescue_keyframe_min_points", o.rescue_keyframe_min_points, {4, 5000})
      .doc("or this many when made while coasting with too few tracks");
  p.optional("gyro_prior", o.gyro_prior)
      .doc("gyro rotation for the prediction and the consistency check");
  p.optional("max_gyro_disagreement_deg", o.max_gyro_disagreement_deg, {0.1, 180})
      .doc("PnP vs gyro rotation over one interval (degrees)");
  p.optional("gravity_time_constant_s", o.gravity_time_constant_s, {0, 1e6})
      .doc("roll/pitch correction toward the accelerometer (s; 0: off)");
  p.optional("gravity_gate_mps2", o.gravity_gate_mps2, {0, 10})
      .doc("only intervals whose gravity estimate is this close to g (m/s²)");
  p.optional("max_coast_s", o.max_coast_s, {0, 10})
      .doc(
          "failed frames are coasted through for this long after the last tracked one (s; 0: every "
          "failed frame a loss)");
  p.optional("coast_quality", o.coast_quality, {0.01, 1})
      .doc("tracking_quality of a coasted frame");
  p.optional("coast_velocity_sigma_mps", o.coast_velocity_sigma_mps, {0, 100})
      .doc("constant-velocity error while coasting, for the covariance (m/s)");
  p.optional("coast_gyro_sigma_radps", o.coast_gyro_sigma_radps, {0, 10})
      .doc("gyro rate error while coasting, for the covariance (rad/s)");
  p.optional("start_sigma_m", o.start_sigma_m, {1e-6, 100})
      .doc("the start pose's position standard deviation (m)");
  p.optional("start_sigma_rad", o.start_sigma_rad, {1e-6, 10})
      .doc("the start pose's rotation standard deviation (rad)");
  p.optional("min_pixel_sigma_px", o.pose.min_pixel_sigma_px, {0.01, 10})
      .doc("floor of σ in the PnP covariance (px)");
  p.optional("gravity_align", c.gravity_align)
      .doc("roll/pitch at start from the accelerometer (else level)");
  p.optional("gravity_window_s", c.gravity_window_s, {0.001, 60})
      .doc("accelerometer samples averaged for it (s)");
  p.optional("imu_max_gap_s", c.imu_max_gap_s, {0.001, 10})
      .doc("longest IMU gap the gyro prior bridges (s; longer: no prior)");
  p.optional("stereo_queue_depth", c.stereo_queue_depth, {1, 64})
      .doc("stereo subscription queue depth");
  p.optional("imu_queue_depth", c.imu_queue_depth, {1, 4096}).doc("IMU subscription queue depth");
  p.optional("use_wheel_odom", c.use_wheel_odom)
      .doc("a ground robot reads its base's wheel_odom (motion prior, coasting's translation)");
  p.optional("max_wheel_coast_s", o.max_wheel_coast_s, {0, 60})
      .doc("with wheel odometry: how long a failure coasts before it is a loss (s)");
  p.optional("coast_wheel_sigma_mps", o.coast_wheel_sigma_mps, {0, 100})
      .doc("with wheel odometry: the wheel velocity's error, for the covariance (m/s)");
  if (o.keyframe_min_inliers < o.pose.min_inliers)
    p.report("keyframe_min_inliers", "must be at least min_inliers");
  return c;
}

Vio::Vio(ComponentContext context, Config config)
    : Component(std::move(context)),
      config_(config),
      odometry_(std::make_unique<StereoOdometry>(config_.odometry)),
      imu_(static_cast<int64_t>(config_.imu_max_gap_s * 1e9)) {}

Vio::~Vio() = default;

Result<void, std::string> Vio::on_configure() {
  // IMU first: at equal stamps its sample is taken before the frame
  create_subscription<msg::Imu>("imu", {.depth = config_.imu_queue_depth},
                                [this](Sample<msg::Imu>&& s) { on_imu(*s); });
  create_subscription<msg::StereoFrame>("stereo", {.depth = config_.stereo_queue_depth},
                                        [this](Sample<msg::StereoFrame>&& s) { on_stereo(*s); });
  odom_ = create_publisher<msg::Odometry>("odom", {.pool_size = 8});
  if (!team().empty()) {
    const auto it = std::find_if(team().begin(), team().end(),
                                 [&](const TeamMember& m) { return m.id == robot_id(); });
    if (it == team().end())
      return make_unexpected("robot id " + std::to_string(robot_id()) +
                             " is not in the launch file's robots: section (its start pose is "
                             "the origin of its odometry)");
    const bool ground =
        it->kind == robot::RobotKind::kGround;  // a ground robot's body frame is on the floor
    start_position_m_ = {it->start_x_m, it->start_y_m, ground ? 0.0 : it->start_z_m};
    start_yaw_rad_ = it->start_yaw_rad;
    // a multirotor has no wheels: it reads none even when the team's launch asks
    if (config_.use_wheel_odom && ground)
      create_subscription<msg::Odometry>("wheel_odom", {.depth = 64},
                                         [this](Sample<msg::Odometry>&& s) { on_wheel_odom(*s); });
  } else {
    SCANCREW_LOG_INFO("%s: no robots: section, odometry starts at the origin",
                      qualified_name().c_str());
  }
  return {};
}

void Vio::reject(InputError error, int64_t stamp_ns) {
  if (stats_.rejected[static_cast<size_t>(error)]++ == 0)
    SCANCREW_LOG_WARN("%s: skipped input at t = %.3f s: %s (further ones are counted)",
                      qualified_name().c_str(), static_cast<double>(stamp_ns) * 1e-9,
                      std::string(to_string(error)).c_str());
}

void Vio::on_imu(const msg::Imu& imu) {
  ++stats_.imu_samples;
  if (const InputError e = check_imu(imu); e != InputError::kNone)
    return reject(e, imu.header.stamp_ns);
  if (!imu_.add(imu.header.stamp_ns, msg::to_eigen(imu.linear_acceleration_mps2),
                msg::to_eigen(imu.angular_velocity_radps)))
    reject(InputError::kStampNotIncreasing, imu.header.stamp_ns);
}

void Vio::on_wheel_odom(const msg::Odometry& odom) {
  const Eigen::Vector3d v = msg::to_eigen(odom.linear_velocity_mps);
  if (!v.allFinite()) return reject(InputError::kBadWheelOdom, odom.header.stamp_ns);
  if (!wheels_.add(odom.header.stamp_ns, v))
    reject(InputError::kStampNotIncreasing, odom.header.stamp_ns);
}

void Vio::start(const msg::StereoFrame& frame) {
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  T_world_body.translation() = start_position_m_;
  Eigen::Quaterniond attitude(Eigen::AngleAxisd(start_yaw_rad_, Eigen::Vector3d::UnitZ()));
  const auto window = static_cast<int64_t>(config_.gravity_window_s * 1e9);
  const auto accel = imu_.mean_accel(frame.header.stamp_ns, window);
  constexpr double kG = 9.80665;
  if (config_.gravity_align && accel && accel->norm() > 0.5 * kG && accel->norm() < 1.5 * kG) {
    attitude = gravity_aligned_attitude(*accel, start_yaw_rad_);
  } else if (config_.gravity_align) {
    SCANCREW_LOG_WARN("%s: no usable accelerometer sample before the first frame: starting level",
                      qualified_name().c_str());
  }
  T_world_body.linear() = attitude.toRotationMatrix();
  odometry_->set_start(T_world_body);
}

void Vio::on_stereo(const msg::StereoFrame& frame) {
  ++stats_.frames;
  const int64_t stamp = frame.header.stamp_ns;
  if (const InputError e = check_stereo(frame); e != InputError::kNone) return reject(e, stamp);
  if (stamp == msg::kStampUnset || stamp <= last_frame_ns_)
    return reject(InputError::kStampNotIncreasing, stamp);
  const auto t0 = std::chrono::steady_clock::now();
  if (!odometry_->started()) start(frame);
  ImuInterval interval;
  if (last_frame_ns_ != msg::kStampUnset) {
    interval.q_prevbody_body = imu_.rotation(last_frame_ns_, stamp);
    interval.mean_specific_force_mps2 = imu_.mean_accel(stamp, stamp - last_frame_ns_);
    interval.wheel_velocity_mps = wheels_.mean_velocity(last_frame_ns_, stamp);
  }
  last_frame_ns_ = stamp;
  imu_.drop_before(stamp);
  wheels_.drop_before(stamp);

  StereoInput input;
  const auto w = static_cast<int>(frame.intrinsics.width);
  const auto h = static_cast<int>(frame.intrinsics.height);
  input.left = {frame.left.data(), w, h};
  input.right = {frame.right.data(), w, h};
  input.intrinsics = frame.intrinsics;
  input.baseline_m = frame.baseline_m;
  input.T_body_cam = msg::to_eigen(frame.T_body_cam);
  input.stamp_ns = stamp;
  const TrackingResult result = odometry_->process(input, interval);
  note_time(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());

  if (result.status == TrackingStatus::kLost) {
    ++stats_.losses[static_cast<size_t>(result.loss)];
    SCANCREW_LOG_WARN("%s: tracking lost at t = %.3f s (%s): reset %u, %s",
                      qualified_name().c_str(), static_cast<double>(stamp) * 1e-9,
                      std::string(to_string(result.loss)).c_str(), odometry_->resets(),
                      result.keyframe_points > 0 ? "re-initialised at the last good pose"
                                                 : "re-initialising when the images allow");
    lost_logged_ = result.keyframe_points == 0;
  } else if (result.status == TrackingStatus::kNotInitialised && !lost_logged_) {
    SCANCREW_LOG_WARN("%s: cannot initialise at t = %.3f s: too few stereo corners",
                      qualified_name().c_str(), static_cast<double>(stamp) * 1e-9);
    lost_logged_ = true;
  } else if (result.status == TrackingStatus::kInitialised && lost_logged_) {
    SCANCREW_LOG_INFO("%s: tracking resumed at t = %.3f s (%zu keyframe points)",
                      qualified_name().c_str(), static_cast<double>(stamp) * 1e-9,
                      result.keyframe_points);
    lost_logged_ = false;
  }
  publish(frame, result);
}

void Vio::publish(const msg::StereoFrame& frame, const TrackingResult& result) {
  auto loan = odom_.loan();
  if (!loan) return;
  msg::Odometry& odom = **loan;
  const int64_t stamp = frame.header.stamp_ns;
  odom.header.stamp_ns = stamp;
  odom.T_world_body = msg::to_msg(result.T_world_body);
  odom.tracking_quality = result.quality;
  odom.tracking_resets = odometry_->resets();
  for (size_t r = 0; r < 6; ++r)  // row-major; x y z then the small rotation angles
    for (size_t col = 0; col < 6; ++col)
      odom.pose_covariance[6 * r + col] =
          result.covariance(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(col));
  odom.linear_velocity_mps = {};
  odom.angular_velocity_radps = {};
  const bool valid = result.quality > 0;
  if (valid && last_published_ns_ != msg::kStampUnset && stamp > last_published_ns_) {
    // world-frame velocity and body-frame rate over the last interval
    const double dt = static_cast<double>(stamp - last_published_ns_) * 1e-9;
    odom.linear_velocity_mps = msg::to_msg(
        Eigen::Vector3d((result.T_world_body.translation() - last_published_.translation()) / dt));
    const Eigen::AngleAxisd turn(last_published_.linear().transpose() *
                                 result.T_world_body.linear());
    odom.angular_velocity_radps = msg::to_msg(Eigen::Vector3d(turn.axis() * turn.angle() / dt));
  }
  if (valid) {
    last_published_ = result.T_world_body;
    last_published_ns_ = stamp;
  } else {
    last_published_ns_ = msg::kStampUnset;  // no velocity across a loss
    ++stats_.untracked_frames;
  }
  if (odom_.publish(std::move(*loan))) ++stats_.published;
}

void Vio::note_time(double ms) {
  recent_frame_ms_[timed_frames_ % recent_frame_ms_.size()] = static_cast<float>(ms);
  ++timed_frames_;
  frame_ms_sum_ += ms;
  stats_.max_frame_ms = std::max(stats_.max_frame_ms, ms);
}

VioStats Vio::stats() const {
  VioStats s = stats_;
  s.resets = odometry_->resets();
  s.keyframes = odometry_->keyframes();
  s.coasted_frames = odometry_->coasted_frames();
  if (timed_frames_ > 0) {
    s.mean_frame_ms = frame_ms_sum_ / static_cast<double>(timed_frames_);
    const size_t n = std::min<size_t>(timed_frames_, recent_frame_ms_.size());
    std::array<float, 1024> sorted = recent_frame_ms_;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(n / 2),
                     sorted.begin() + static_cast<std::ptrdiff_t>(n));
    s.p50_frame_ms = sorted[n / 2];
  }
  return s;
}

void Vio::on_deactivate() {
  const VioStats s = stats();
  uint64_t rejected = 0;
  for (const uint64_t n : s.rejected) rejected += n;
  std::string reasons;  // "; losses: too few PnP inliers 3, ..." (none when there were none)
  for (size_t i = 0; i < s.losses.size(); ++i)
    if (s.losses[i] > 0)
      reasons += (reasons.empty() ? "; losses: " : ", ") +
                 std::string(to_string(static_cast<LossReason>(i))) + " " +
                 std::to_string(s.losses[i]);
  SCANCREW_LOG_INFO(
      "%s: %llu frames, %llu odometry, %llu keyframes, %u tracking losses, %llu frames coasted, "
      "%llu frames skipped (bad input), %.2f ms/frame mean, %.2f max%s",
      qualified_name().c_str(), static_cast<unsigned long long>(s.frames),
      static_cast<unsigned long long>(s.published), static_cast<unsigned long long>(s.keyframes),
      s.resets, static_cast<unsigned long long>(s.coasted_frames),
      static_cast<unsigned long long>(rejected), s.mean_frame_ms, s.max_frame_ms, reasons.c_str());
}

void Vio::summarize(RunSummary& into) const {
  const VioStats s = stats();
  RunSummary::Odometry& o = into.odometry[robot_id()];
  o.frames = s.frames;
  o.losses = s.resets;
  o.coasted_frames = s.coasted_frames;
  for (size_t i = 0; i < s.losses.size(); ++i)
    if (s.losses[i] > 0)
      o.losses_by_reason[std::string(to_string(static_cast<LossReason>(i)))] = s.losses[i];
  o.mean_frame_ms = s.mean_frame_ms;
  o.max_frame_ms = s.max_frame_ms;
}

SCANCREW_REGISTER_COMPONENT(Vio, "vio")

}  // namespace scancrew::vio
