#include "eval/odometry_error.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "interfaces/eigen_conversions.hpp"

namespace scancrew::eval {

namespace {

bool finite(const msg::Pose3& p) {
  return std::isfinite(p.position.x) && std::isfinite(p.position.y) &&
         std::isfinite(p.position.z) && std::isfinite(p.orientation.w) &&
         std::isfinite(p.orientation.x) && std::isfinite(p.orientation.y) &&
         std::isfinite(p.orientation.z);
}

std::vector<StampedPose> sorted(const std::vector<StampedPose>& poses) {
  std::vector<StampedPose> s = poses;
  std::stable_sort(s.begin(), s.end(), [](const StampedPose& a, const StampedPose& b) {
    return a.stamp_ns < b.stamp_ns;
  });
  return s;
}

// The transform taking the estimate's positions onto the ground truth's.
Eigen::Isometry3d alignment(const std::vector<Eigen::Isometry3d>& estimate,
                            const std::vector<Eigen::Isometry3d>& truth, Alignment kind) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  const auto n = static_cast<Eigen::Index>(estimate.size());
  if (kind == Alignment::kNone || n < 2) return t;
  Eigen::Matrix3Xd p(3, n), q(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    p.col(i) = estimate[static_cast<size_t>(i)].translation();
    q.col(i) = truth[static_cast<size_t>(i)].translation();
  }
  if (kind == Alignment::kSe3) {
    t.matrix() = Eigen::umeyama(p, q, false);
    return t;
  }
  // yaw + translation: the rotation about z that best maps the centred xy positions
  const Eigen::Vector3d p_mean = p.rowwise().mean(), q_mean = q.rowwise().mean();
  double sin_sum = 0, cos_sum = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d a = p.col(i) - p_mean, b = q.col(i) - q_mean;
    sin_sum += a.x() * b.y() - a.y() * b.x();
    cos_sum += a.x() * b.x() + a.y() * b.y();
  }
  t.linear() =
      Eigen::AngleAxisd(std::atan2(sin_sum, cos_sum), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = q_mean - t.linear() * p_mean;
  return t;
}

}  // namespace

std::string_view to_string(Alignment alignment) {
  switch (alignment) {
    case Alignment::kNone:
      return "none";
    case Alignment::kSe3:
      return "se3";
    case Alignment::kYaw:
      return "yaw";
  }
  return "unknown";
}

Result<OdometryError, std::string> odometry_error(const std::vector<StampedPose>& estimate,
                                                  const std::vector<StampedPose>& ground_truth,
                                                  const OdometryErrorConfig& config) {
  if (!(config.segment_length_m > 0))
    return make_unexpected(std::string("segment_length_m must be > 0"));
  if (config.max_stamp_difference_ns < 0)
    return make_unexpected(std::string("max_stamp_difference_ns must be >= 0"));
  for (const auto* poses : {&estimate, &ground_truth})
    for (const StampedPose& p : *poses)
      if (!finite(p.pose))
        return make_unexpected("a pose at t = " + std::to_string(p.stamp_ns) + " ns is not finite");

  // match each estimate with the ground truth of the nearest stamp, within the tolerance
  const std::vector<StampedPose> est = sorted(estimate), gt = sorted(ground_truth);
  std::vector<Eigen::Isometry3d> e, g;
  for (const StampedPose& p : est) {
    const auto it =
        std::lower_bound(gt.begin(), gt.end(), p.stamp_ns,
                         [](const StampedPose& a, int64_t stamp) { return a.stamp_ns < stamp; });
    const StampedPose* best = nullptr;
    if (it != gt.end()) best = &*it;
    if (it != gt.begin()) {
      const StampedPose* before = &*std::prev(it);
      if (best == nullptr || p.stamp_ns - before->stamp_ns < best->stamp_ns - p.stamp_ns)
        best = before;
    }
    if (best == nullptr || std::llabs(best->stamp_ns - p.stamp_ns) > config.max_stamp_difference_ns)
      continue;
    e.push_back(msg::to_eigen(p.pose));
    g.push_back(msg::to_eigen(best->pose));
  }
  if (e.empty()) return make_unexpected(std::string("no estimate matches a ground-truth stamp"));

  OdometryError r;
  r.matched = e.size();
  const Eigen::Isometry3d align = alignment(e, g, config.alignment);
  for (Eigen::Isometry3d& t : e) t = align * t;

  // ATE
  double sum2 = 0;
  for (size_t i = 0; i < e.size(); ++i) {
    const double d = (e[i].translation() - g[i].translation()).norm();
    sum2 += d * d;
    r.ate_max_m = std::max(r.ate_max_m, d);
  }
  r.ate_rmse_m = std::sqrt(sum2 / static_cast<double>(e.size()));

  // path length along the ground truth
  std::vector<double> along(g.size(), 0.0);
  for (size_t i = 1; i < g.size(); ++i)
    along[i] = along[i - 1] + (g[i].translation() - g[i - 1].translation()).norm();
  r.distance_m = along.back();

  // RPE over segments of length L (KITTI): each start, the first pose >= L later
  const double l = config.segment_length_m;
  double rpe_sum = 0, rpe_sum2 = 0, rot_sum = 0;
  size_t j = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    j = std::max(j, i + 1);
    while (j < g.size() && along[j] - along[i] < l) ++j;
    if (j >= g.size()) break;
    const Eigen::Isometry3d motion_gt = g[i].inverse() * g[j];
    const Eigen::Isometry3d motion_est = e[i].inverse() * e[j];
    const Eigen::Isometry3d error = motion_gt.inverse() * motion_est;
    const double percent = 100.0 * error.translation().norm() / l;
    rpe_sum += percent;
    rpe_sum2 += percent * percent;
    r.rpe_max_percent = std::max(r.rpe_max_percent, percent);
    rot_sum += Eigen::AngleAxisd(error.rotation()).angle() * 180.0 / M_PI / l;
    ++r.segments;
  }
  if (r.segments > 0) {
    const auto n = static_cast<double>(r.segments);
    r.rpe_mean_percent = rpe_sum / n;
    r.rpe_rmse_percent = std::sqrt(rpe_sum2 / n);
    r.rpe_rotation_deg_per_m = rot_sum / n;
  }
  return r;
}

}  // namespace scancrew::eval
