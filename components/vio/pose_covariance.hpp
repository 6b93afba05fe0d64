#pragma once

// Pose covariances of the odometry: 6x6, position (m, world axes) then rotation (rad, a
// small world-frame angle vector), of the left camera's pose; the body's pose is published
// with it (the lever arm between them is left out).
//
//   per frame:     Σ_world = F Σ_kf Fᵀ + G Σ_rel Gᵀ — the keyframe's covariance carried to
//                  the frame (its rotation error moves the frame by the distance travelled
//                  since the keyframe) plus the PnP estimate's, σ²(JᵀJ)⁻¹ (PoseEstimate)
//   new keyframe:  Σ_kf ← that frame's Σ_world, so the covariance accumulates across
//                  keyframe switches and grows with the distance travelled
//   coasting:      the last tracked frame's Σ_world plus a constant-velocity model's growth
//                  (velocity and gyro errors held over the coasted time)
//
// Plain functions, no allocation.

#include <Eigen/Geometry>

namespace scancrew::vio {

using Covariance6 = Eigen::Matrix<double, 6, 6>;

// The covariance of T_ref_cam (position, rotation in the reference frame) from that of the
// (rvec, tvec) of its inverse T_cam_ref, to first order.
Covariance6 camera_in_reference(const Eigen::Isometry3d& T_cam_ref, const Covariance6& cov_rt);

// The world covariance of T_world_cam = T_world_kf · T_kf_cam from the keyframe's world
// covariance and the relative pose's (camera_in_reference), taken as independent.
Covariance6 compose(const Eigen::Isometry3d& T_world_kf, const Covariance6& cov_world_kf,
                    const Eigen::Isometry3d& T_kf_cam, const Covariance6& cov_kf_cam);

// What coasting for coast_s seconds adds: the velocity error velocity_sigma_mps and the
// gyro's rate error gyro_sigma_radps, each held over the whole time (variance ∝ coast_s²).
Covariance6 coast_growth(double coast_s, double velocity_sigma_mps, double gyro_sigma_radps);

}  // namespace scancrew::vio
