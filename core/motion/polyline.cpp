#include "core/motion/polyline.hpp"

#include <algorithm>
#include <limits>

namespace scancrew::motion {

Eigen::Vector3d Polyline::project(const Eigen::Vector3d& p) const {
  return planar_ ? Eigen::Vector3d(p.x(), p.y(), 0.0) : p;
}

void Polyline::assign(const Eigen::Vector3d& start, std::span<const Eigen::Vector3d> waypoints,
                      double max_length_m, bool planar) {
  planar_ = planar;
  points_.clear();
  cumulative_.clear();
  points_.push_back(project(start));
  cumulative_.push_back(0.0);
  const double limit = std::max(0.0, max_length_m);
  for (const Eigen::Vector3d& w : waypoints) {
    const Eigen::Vector3d q = project(w);
    const double step = (q - points_.back()).norm();
    if (!(step > 1e-9)) continue;  // duplicates (and NaN steps) add nothing
    const double s = cumulative_.back();
    if (s + step >= limit) {
      const double left = limit - s;
      if (left > 1e-9) {
        points_.push_back(points_.back() + (q - points_.back()) * (left / step));
        cumulative_.push_back(limit);
      }
      break;
    }
    points_.push_back(q);
    cumulative_.push_back(s + step);
  }
}

size_t Polyline::segment_at(double s) const {
  // the segment [i, i + 1] holding s; the last one for s beyond the end
  const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
  const auto i = static_cast<size_t>(std::max<std::ptrdiff_t>(it - cumulative_.begin() - 1, 0));
  return std::min(i, points_.size() - 2);
}

Eigen::Vector3d Polyline::at(double s) const {
  if (points_.size() < 2) return points_.empty() ? Eigen::Vector3d::Zero() : points_.front();
  s = std::clamp(s, 0.0, length_m());
  const size_t i = segment_at(s);
  const double len = cumulative_[i + 1] - cumulative_[i];
  const double t = std::clamp((s - cumulative_[i]) / len, 0.0, 1.0);
  return points_[i] + (points_[i + 1] - points_[i]) * t;
}

Eigen::Vector3d Polyline::tangent(double s) const {
  if (points_.size() < 2) return Eigen::Vector3d::Zero();
  const size_t i = segment_at(std::clamp(s, 0.0, length_m()));
  return (points_[i + 1] - points_[i]).normalized();
}

Polyline::Closest Polyline::closest(const Eigen::Vector3d& p_in) const {
  const Eigen::Vector3d p = project(p_in);
  Closest best{(p - points_.front()).norm(), 0.0};
  for (size_t i = 0; i + 1 < points_.size(); ++i) {
    const Eigen::Vector3d d = points_[i + 1] - points_[i];
    const double len = cumulative_[i + 1] - cumulative_[i];
    const double t = std::clamp((p - points_[i]).dot(d) / (len * len), 0.0, 1.0);
    const double dist = (p - (points_[i] + d * t)).norm();
    if (dist < best.distance_m) best = {dist, cumulative_[i] + t * len};
  }
  return best;
}

}  // namespace scancrew::motion
