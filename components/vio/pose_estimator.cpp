#include "components/vio/pose_estimator.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace scancrew::vio {

struct PoseEstimator::Impl {
  PoseEstimatorConfig config;
  std::vector<cv::Point3d> object, object_in;
  std::vector<cv::Point2d> image, image_in, projected;
  std::vector<int> inlier_index;
  cv::Mat jacobian;

  // σ²(JᵀJ)⁻¹ over the inliers (object_in/image_in hold them); identity·1e6 if singular
  Eigen::Matrix<double, 6, 6> covariance(const cv::Mat& rvec, const cv::Mat& tvec,
                                         const cv::Matx33d& k, double sigma_px);
};

Eigen::Matrix<double, 6, 6> PoseEstimator::Impl::covariance(const cv::Mat& rvec,
                                                            const cv::Mat& tvec,
                                                            const cv::Matx33d& k, double sigma_px) {
  object_in.clear();
  image_in.clear();
  for (const int i : inlier_index) object_in.push_back(object[static_cast<size_t>(i)]);
  cv::projectPoints(object_in, rvec, tvec, k, cv::noArray(), image_in, jacobian);
  // columns: rvec (3), tvec (3), then the intrinsics
  Eigen::Matrix<double, 6, 6> jtj = Eigen::Matrix<double, 6, 6>::Zero();
  for (int r = 0; r < jacobian.rows; ++r) {
    const auto* row = jacobian.ptr<double>(r);
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> j(row);
    jtj.noalias() += j * j.transpose();
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(jtj);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0))
    return Eigen::Matrix<double, 6, 6>::Identity() * 1e6;
  return sigma_px * sigma_px * ldlt.solve(Eigen::Matrix<double, 6, 6>::Identity());
}

std::string_view to_string(PoseStatus status) {
  switch (status) {
    case PoseStatus::kOk:
      return "ok";
    case PoseStatus::kTooFewPoints:
      return "too few tracked points";
    case PoseStatus::kSolverFailed:
      return "PnP RANSAC found no pose";
    case PoseStatus::kTooFewInliers:
      return "too few PnP inliers";
  }
  return "unknown";
}

PoseEstimator::PoseEstimator(const PoseEstimatorConfig& config) : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
}

PoseEstimator::~PoseEstimator() = default;

void PoseEstimator::estimate(std::span<const Eigen::Vector3d> points_ref,
                             std::span<const Eigen::Vector2f> pixels,
                             const msg::CameraIntrinsics& intrinsics, PoseEstimate& out) {
  Impl& m = *impl_;
  const PoseEstimatorConfig& c = m.config;
  out.inlier.assign(points_ref.size(), 0);
  out.inliers = 0;
  out.rms_reprojection_px = 0;
  const size_t n = points_ref.size();
  if (n != pixels.size() || n < 4 || n < c.min_inliers) {
    out.status = PoseStatus::kTooFewPoints;
    return;
  }
  m.object.clear();
  m.image.clear();
  for (size_t i = 0; i < n; ++i) {
    m.object.emplace_back(points_ref[i].x(), points_ref[i].y(), points_ref[i].z());
    m.image.emplace_back(pixels[i].x(), pixels[i].y());
  }
  const cv::Matx33d k(intrinsics.fx, 0, intrinsics.cx, 0, intrinsics.fy, intrinsics.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  bool found = false;
  try {
    // minimal solver inside RANSAC (OpenCV then re-fits the model to its inliers)
    found = cv::solvePnPRansac(m.object, m.image, k, cv::noArray(), rvec, tvec, false,
                               static_cast<int>(c.ransac_iterations),
                               static_cast<float>(c.ransac_reprojection_px), c.ransac_confidence,
                               m.inlier_index,
                               c.solver == PnpSolver::kAp3p ? cv::SOLVEPNP_AP3P : cv::SOLVEPNP_P3P);
  } catch (const cv::Exception&) {
    found = false;  // degenerate configurations make the solvers throw
  }
  if (!found || rvec.empty() || tvec.empty()) {
    out.status = PoseStatus::kSolverFailed;
    return;
  }
  // refinement on the inliers, then the inliers of the refined pose, twice
  const double threshold2 = c.ransac_reprojection_px * c.ransac_reprojection_px;
  for (int pass = 0; pass < (c.refine ? 2 : 1); ++pass) {
    if (c.refine && m.inlier_index.size() >= 4) {
      m.object_in.clear();
      m.image_in.clear();
      for (const int i : m.inlier_index) {
        m.object_in.push_back(m.object[static_cast<size_t>(i)]);
        m.image_in.push_back(m.image[static_cast<size_t>(i)]);
      }
      try {
        cv::solvePnPRefineLM(m.object_in, m.image_in, k, cv::noArray(), rvec, tvec);
      } catch (const cv::Exception&) {
        break;  // keep the RANSAC pose
      }
    }
    cv::projectPoints(m.object, rvec, tvec, k, cv::noArray(), m.projected);
    m.inlier_index.clear();
    double sum2 = 0;
    for (size_t i = 0; i < n; ++i) {
      const cv::Point2d d = m.projected[i] - m.image[i];
      const double e2 = d.dot(d);
      if (!(e2 <= threshold2)) continue;
      m.inlier_index.push_back(static_cast<int>(i));
      sum2 += e2;
    }
    out.rms_reprojection_px =
        m.inlier_index.empty() ? 0 : std::sqrt(sum2 / static_cast<double>(m.inlier_index.size()));
  }
  for (const int i : m.inlier_index) out.inlier[static_cast<size_t>(i)] = 1;
  out.inliers = m.inlier_index.size();
  if (out.inliers >= 4)
    out.covariance_rt =
        m.covariance(rvec, tvec, k, std::max(out.rms_reprojection_px, c.min_pixel_sigma_px));
  cv::Matx33d rotation;
  cv::Rodrigues(rvec, rotation);
  Eigen::Matrix3d r;
  cv::cv2eigen(rotation, r);
  out.T_cam_ref.setIdentity();
  out.T_cam_ref.linear() = r;
  out.T_cam_ref.translation() =
      Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  out.status = out.inliers >= c.min_inliers ? PoseStatus::kOk : PoseStatus::kTooFewInliers;
}

}  // namespace scancrew::vio
