#pragma once

// PoseEstimator: the pose of a camera from 2D-3D matches (keyframe points seen in the
// current image), as in eVO (thesis 1.2.2): a minimal P3P solver [Fischler & Bolles 1981;
// Quan & Lan 1999] inside RANSAC (OpenCV's solvePnPRansac, AP3P by default [Ke &
// Roumeliotis 2017]), then a Levenberg-Marquardt refinement on the inliers, whose inlier
// set is then recomputed. Returns a status, never throws. OpenCV stays in the .cpp.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

#include "core/enum_names.hpp"
#include "interfaces/geometry.hpp"

namespace scancrew::vio {

// The minimal solver inside RANSAC (param `pnp_solver`): AP3P or Gao's P3P.
enum class PnpSolver : uint8_t { kAp3p, kP3p };

inline constexpr EnumNames<PnpSolver, 2> kPnpSolverNames = {
    {{PnpSolver::kAp3p, "ap3p"}, {PnpSolver::kP3p, "p3p"}}};

struct PoseEstimatorConfig {
  double ransac_reprojection_px = 1.5;  // inlier threshold
  uint32_t ransac_iterations = 100;
  double ransac_confidence = 0.995;
  PnpSolver solver = PnpSolver::kAp3p;  // minimal solver: AP3P or Gao's P3P
  bool refine = true;                   // LM on the inliers, then inliers again
  uint32_t min_inliers = 15;            // fewer: kTooFewInliers
  double min_pixel_sigma_px = 0.3;      // floor of σ in the pose covariance
};

enum class PoseStatus : uint8_t { kOk, kTooFewPoints, kSolverFailed, kTooFewInliers };
std::string_view to_string(PoseStatus status);

struct PoseEstimate {
  PoseStatus status = PoseStatus::kTooFewPoints;
  Eigen::Isometry3d T_cam_ref = Eigen::Isometry3d::Identity();  // maps reference points to camera
  std::vector<uint8_t> inlier;                                  // per match
  size_t inliers = 0;
  double rms_reprojection_px = 0;  // over the inliers
  // Covariance of (rvec, tvec) of T_cam_ref (Rodrigues vector rad, m) when status is kOk:
  // σ²(JᵀJ)⁻¹ with J the reprojection Jacobian over the inliers and σ the inliers' RMS
  // reprojection error, at least min_pixel_sigma_px (a Gauss-Newton covariance, after the
  // LM refinement; Hartley & Zisserman 2004, 5.2).
  Eigen::Matrix<double, 6, 6> covariance_rt = Eigen::Matrix<double, 6, 6>::Identity();
};

class PoseEstimator {
 public:
  explicit PoseEstimator(const PoseEstimatorConfig& config);
  ~PoseEstimator();
  PoseEstimator(const PoseEstimator&) = delete;
  PoseEstimator& operator=(const PoseEstimator&) = delete;

  // points_ref[i] (m, reference frame) is seen at pixels[i] in the camera. Fills `out`.
  void estimate(std::span<const Eigen::Vector3d> points_ref,
                std::span<const Eigen::Vector2f> pixels, const msg::CameraIntrinsics& intrinsics,
                PoseEstimate& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::vio
