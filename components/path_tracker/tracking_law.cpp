#include "components/path_tracker/tracking_law.hpp"

#include <visp3/core/vpException.h>
#include <visp3/core/vpHomogeneousMatrix.h>
#include <visp3/visual_features/vpFeatureThetaU.h>
#include <visp3/visual_features/vpFeatureTranslation.h>
#include <visp3/vs/vpAdaptiveGain.h>
#include <visp3/vs/vpServo.h>

#include <cmath>

namespace scancrew::path_tracker {

double yaw_of(const Eigen::Matrix3d& R_world_body) {
  return std::atan2(R_world_body(1, 0), R_world_body(0, 0));
}

Eigen::Isometry3d level_pose(const Eigen::Vector3d& position_m, double yaw_rad) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = position_m;
  return t;
}

// The task and its features: vpServo keeps pointers to the features, so they live
// together, at a fixed address (the Impl is never moved, only its owner).
struct TrackingLaw::Impl {
  vpServo task;
  vpFeatureTranslation translation{vpFeatureTranslation::cdMc};
  vpFeatureThetaU theta_u{vpFeatureThetaU::cdRc};

  explicit Impl(const TrackingLawConfig& c) {
    task.setServo(vpServo::EYEINHAND_CAMERA);
    task.setInteractionMatrixType(vpServo::CURRENT, vpServo::PSEUDO_INVERSE);
    if (c.gain_at_zero > c.gain)
      task.setLambda(vpAdaptiveGain(c.gain_at_zero, c.gain, c.gain_slope));
    else
      task.setLambda(c.gain);
    // s* = 0 for both features (the desired pose is reached when c = c*)
    task.addFeature(translation);
    task.addFeature(theta_u);
  }
};

TrackingLaw::TrackingLaw(TrackingLawConfig config)
    : config_(config), impl_(std::make_unique<Impl>(config_)) {}
TrackingLaw::~TrackingLaw() = default;
TrackingLaw::TrackingLaw(TrackingLaw&&) noexcept = default;
TrackingLaw& TrackingLaw::operator=(TrackingLaw&&) noexcept = default;

LawOutput TrackingLaw::compute(const Eigen::Isometry3d& T_world_body,
                               const Eigen::Isometry3d& T_world_target) {
  // level both poses: the twist is expressed in the body's heading frame
  const double body_yaw = yaw_of(T_world_body.linear());
  const double target_yaw = yaw_of(T_world_target.linear());
  const Eigen::Isometry3d T_world_c = level_pose(T_world_body.translation(), body_yaw);
  const Eigen::Isometry3d T_world_cd = level_pose(T_world_target.translation(), target_yaw);
  const Eigen::Isometry3d T_cd_c = T_world_cd.inverse() * T_world_c;

  LawOutput out;
  out.offset_body_m = T_world_c.inverse() * T_world_target.translation();
  out.yaw_error_rad = std::remainder(target_yaw - body_yaw, 2 * M_PI);

  vpHomogeneousMatrix T_cd_c_vp;  // ViSP's cdMc
  for (unsigned r = 0; r < 3; ++r) {
    for (unsigned c = 0; c < 3; ++c) T_cd_c_vp[r][c] = T_cd_c.linear()(r, c);
    T_cd_c_vp[r][3] = T_cd_c.translation()(r);
  }
  try {
    impl_->translation.buildFrom(T_cd_c_vp);
    impl_->theta_u.buildFrom(T_cd_c_vp);
    const vpColVector v = impl_->task.computeControlLaw();
    out.twist.linear_mps = {v[0], v[1], v[2]};
    // level poses: the rotation is about z only; roll and pitch rates stay zero
    out.twist.angular_radps = {0.0, 0.0, v[5]};
  } catch (const vpException&) {
    out.twist = {};
    out.valid = false;
  }
  return out;
}

}  // namespace scancrew::path_tracker
