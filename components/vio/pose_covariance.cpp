#include "components/vio/pose_covariance.hpp"

namespace scancrew::vio {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d s;
  s << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return s;
}

}  // namespace

Covariance6 camera_in_reference(const Eigen::Isometry3d& T_cam_ref, const Covariance6& cov_rt) {
  // R' = exp([δθ]×)R, t' = t + δt: the camera centre c = -Rᵀt moves by
  // -Rᵀδt - Rᵀ[t]×δθ and its orientation Rᵀ turns by -Rᵀδθ (the Rodrigues vector's change
  // taken as δθ, exact near identity and close for the small turns between keyframe and frame)
  const Eigen::Matrix3d rt = T_cam_ref.linear().transpose();
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
  a.block<3, 3>(0, 0) = -rt * skew(T_cam_ref.translation());
  a.block<3, 3>(0, 3) = -rt;
  a.block<3, 3>(3, 0) = -rt;
  return a * cov_rt * a.transpose();
}

Covariance6 compose(const Eigen::Isometry3d& T_world_kf, const Covariance6& cov_world_kf,
                    const Eigen::Isometry3d& T_kf_cam, const Covariance6& cov_kf_cam) {
  // δp = δp_kf - [d]× δφ_kf + R δc, δφ = δφ_kf + R δφ_rel, d = R c (world displacement)
  const Eigen::Matrix3d r = T_world_kf.linear();
  const Eigen::Vector3d d = r * T_kf_cam.translation();
  Eigen::Matrix<double, 6, 6> f = Eigen::Matrix<double, 6, 6>::Identity();
  f.block<3, 3>(0, 3) = -skew(d);
  Eigen::Matrix<double, 6, 6> g = Eigen::Matrix<double, 6, 6>::Zero();
  g.block<3, 3>(0, 0) = r;
  g.block<3, 3>(3, 3) = r;
  Covariance6 out = f * cov_world_kf * f.transpose() + g * cov_kf_cam * g.transpose();
  return 0.5 * (out + out.transpose());  // symmetric despite rounding
}

Covariance6 coast_growth(double coast_s, double velocity_sigma_mps, double gyro_sigma_radps) {
  Covariance6 q = Covariance6::Zero();
  const double p = velocity_sigma_mps * coast_s, r = gyro_sigma_radps * coast_s;
  q.diagonal() << p * p, p * p, p * p, r * r, r * r, r * r;
  return q;
}

}  // namespace scancrew::vio
