#include "components/mission_monitor/pose_error.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "interfaces/eigen_conversions.hpp"

namespace scancrew::mission_monitor {

namespace {

// truth kept for matching: the odometry answers a frame within a few steps of its capture
constexpr int64_t kTruthKeptNs = 3'000'000'000;
// a robot's latest matched pose counts in a pairwise sample for this long
constexpr int64_t kSampleAgeNs = 1'000'000'000;

Eigen::Isometry3d frame_error(const eval::StampedPose& estimate, const eval::StampedPose& truth) {
  return msg::to_eigen(estimate.pose) * msg::to_eigen(truth.pose).inverse();
}

}  // namespace

PoseError::PoseError(size_t robots) : robots_(robots) {
  for (size_t a = 0; a < robots; ++a)
    for (size_t b = a + 1; b < robots; ++b) pairs_.push_back({.a = a, .b = b});
  sums_.assign(pairs_.size(), 0.0);
}

void PoseError::on_truth(size_t robot, const msg::Odometry& truth) {
  std::vector<eval::StampedPose>& recent = robots_[robot].truth_recent;
  recent.push_back({.stamp_ns = truth.header.stamp_ns, .pose = truth.T_world_body});
  const int64_t oldest = truth.header.stamp_ns - kTruthKeptNs;
  recent.erase(recent.begin(),
               std::find_if(recent.begin(), recent.end(),
                            [oldest](const eval::StampedPose& p) { return p.stamp_ns >= oldest; }));
}

void PoseError::on_estimate(size_t robot, const msg::Odometry& estimate) {
  Robot& r = robots_[robot];
  const int64_t stamp = estimate.header.stamp_ns;
  const auto it = std::find_if(r.truth_recent.begin(), r.truth_recent.end(),
                               [stamp](const eval::StampedPose& p) { return p.stamp_ns == stamp; });
  if (it == r.truth_recent.end()) return;  // no truth of its frame: not scored
  r.estimate.push_back({.stamp_ns = stamp, .pose = estimate.T_world_body});
  r.truth.push_back(*it);
  r.truth_recent.erase(r.truth_recent.begin(), it + 1);
}

void PoseError::sample(int64_t now_ns) {
  for (size_t k = 0; k < pairs_.size(); ++k) {
    Pair& pair = pairs_[k];
    const Robot& a = robots_[pair.a];
    const Robot& b = robots_[pair.b];
    if (a.estimate.empty() || b.estimate.empty()) continue;
    if (now_ns - a.estimate.back().stamp_ns > kSampleAgeNs ||
        now_ns - b.estimate.back().stamp_ns > kSampleAgeNs)
      continue;
    const Eigen::Isometry3d ea = frame_error(a.estimate.back(), a.truth.back());
    const Eigen::Isometry3d eb = frame_error(b.estimate.back(), b.truth.back());
    const Eigen::Vector3d mid = 0.5 * (msg::to_eigen(a.truth.back().pose.position) +
                                       msg::to_eigen(b.truth.back().pose.position));
    const double d = (ea * mid - eb * mid).norm();
    const Eigen::Matrix3d relative = ea.linear().transpose() * eb.linear();
    const double yaw_deg = std::abs(std::atan2(relative(1, 0), relative(0, 0))) * 180.0 / M_PI;
    ++pair.samples;
    sums_[k] += d;
    pair.mean_m = sums_[k] / static_cast<double>(pair.samples);
    pair.max_m = std::max(pair.max_m, d);
    pair.last_m = d;
    pair.max_yaw_deg = std::max(pair.max_yaw_deg, yaw_deg);
  }
}

std::vector<PoseError::Pair> PoseError::pairs() const {
  return pairs_;
}

std::optional<eval::OdometryError> PoseError::robot_error(size_t robot) const {
  const Robot& r = robots_[robot];
  if (r.estimate.empty()) return std::nullopt;
  auto error = eval::odometry_error(r.estimate, r.truth, {.segment_length_m = 1.0});
  if (!error) return std::nullopt;  // a non-finite pose: the odometry's own checks say so
  return *error;
}

}  // namespace scancrew::mission_monitor
