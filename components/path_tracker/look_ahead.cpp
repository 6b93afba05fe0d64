#include "components/path_tracker/look_ahead.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scancrew::path_tracker {

namespace {
constexpr double kMinSegmentM = 1e-6;  // shorter segments have no direction
}

LookAhead::LookAhead(LookAheadConfig config) : config_(config) {}

Eigen::Vector3d LookAhead::flat(const Eigen::Vector3d& p) const {
  return config_.planar ? Eigen::Vector3d(p.x(), p.y(), 0.0) : p;
}

void LookAhead::clear() {
  waypoints_.clear();
  points_.clear();
  arc_m_.clear();
  tangent_yaw_.clear();
  segment_ = 0;
  progress_m_ = 0;
}

Result<void, std::string> LookAhead::set_path(const std::vector<msg::Waypoint>& waypoints) {
  clear();
  if (waypoints.empty()) return make_unexpected(std::string("empty path"));
  for (size_t i = 0; i < waypoints.size(); ++i) {
    const msg::Waypoint& w = waypoints[i];
    if (!std::isfinite(w.position.x) || !std::isfinite(w.position.y) ||
        !std::isfinite(w.position.z) || !std::isfinite(w.yaw_rad))
      return make_unexpected("waypoint " + std::to_string(i) + " is not finite");
  }
  waypoints_ = waypoints;
  points_.reserve(waypoints.size());
  arc_m_.reserve(waypoints.size());
  for (const msg::Waypoint& w : waypoints) {
    points_.push_back(flat({w.position.x, w.position.y, w.position.z}));
    arc_m_.push_back(arc_m_.empty()
                         ? 0.0
                         : arc_m_.back() + (points_.back() - points_[points_.size() - 2]).norm());
  }
  // tangent yaw per segment; a segment without horizontal extent (a climb, a repeated
  // waypoint) takes its neighbour's, the end waypoint's yaw when no segment has one
  const size_t segments = points_.size() - 1;
  tangent_yaw_.assign(segments, std::numeric_limits<double>::quiet_NaN());
  for (size_t j = 0; j < segments; ++j) {
    const double dx = waypoints[j + 1].position.x - waypoints[j].position.x;
    const double dy = waypoints[j + 1].position.y - waypoints[j].position.y;
    if (std::hypot(dx, dy) > kMinSegmentM) tangent_yaw_[j] = std::atan2(dy, dx);
  }
  for (size_t j = 1; j < segments; ++j)
    if (std::isnan(tangent_yaw_[j])) tangent_yaw_[j] = tangent_yaw_[j - 1];
  for (size_t j = segments; j-- > 1;)
    if (std::isnan(tangent_yaw_[j - 1])) tangent_yaw_[j - 1] = tangent_yaw_[j];
  for (size_t j = 0; j < segments; ++j)
    if (std::isnan(tangent_yaw_[j])) tangent_yaw_[j] = waypoints[j + 1].yaw_rad;
  return {};
}

Eigen::Vector3d LookAhead::point_at(double s_m, size_t* segment) const {
  size_t k = std::min(segment_, points_.size() - 1);
  while (k + 1 < points_.size() && arc_m_[k + 1] <= s_m) ++k;
  *segment = std::min(k, points_.size() - 2);
  if (k + 1 >= points_.size()) return points_.back();
  const double len = arc_m_[k + 1] - arc_m_[k];
  const double t = len > kMinSegmentM ? (s_m - arc_m_[k]) / len : 0.0;
  return points_[k] + t * (points_[k + 1] - points_[k]);
}

LookAheadTarget LookAhead::update(const Eigen::Vector3d& position_m) {
  LookAheadTarget out;
  const Eigen::Vector3d p = flat(position_m);
  const size_t n = points_.size();

  // project: the nearest point at or after the progress, within the search window
  if (n >= 2) {
    double best_d = std::numeric_limits<double>::infinity();
    size_t best_j = segment_;
    double best_s = progress_m_;
    const double s_max = progress_m_ + config_.search_window_m;
    for (size_t j = segment_; j + 1 < n && arc_m_[j] <= s_max; ++j) {
      const double len = arc_m_[j + 1] - arc_m_[j];
      const double s_lo = std::max(arc_m_[j], progress_m_);
      const double s_hi = std::min(arc_m_[j + 1], s_max);
      double s = s_lo;
      if (len > kMinSegmentM) {
        const Eigen::Vector3d dir = (points_[j + 1] - points_[j]) / len;
        s = std::clamp(arc_m_[j] + (p - points_[j]).dot(dir), s_lo, s_hi);
      }
      const double t = len > kMinSegmentM ? (s - arc_m_[j]) / len : 0.0;
      const double d = (p - (points_[j] + t * (points_[j + 1] - points_[j]))).norm();
      if (d < best_d - 1e-9) {
        best_d = d;
        best_j = j;
        best_s = s;
      }
    }
    segment_ = best_j;
    progress_m_ = best_s;
    out.cross_track_m = best_d;
  } else {
    out.cross_track_m = (p - points_.front()).norm();
  }
  out.progress_m = progress_m_;
  out.remaining_m = length_m() - progress_m_;
  out.next_index = static_cast<uint32_t>(n - 1);
  for (size_t i = segment_; i < n; ++i) {
    if (arc_m_[i] > progress_m_ + kMinSegmentM) {
      out.next_index = static_cast<uint32_t>(i);
      break;
    }
  }

  // the look-ahead pose
  const double s_target = progress_m_ + config_.distance_m;
  if (n < 2 || s_target >= length_m() - kMinSegmentM) {
    const msg::Waypoint& w = waypoints_.back();
    out.position_m = {w.position.x, w.position.y, w.position.z};
    out.yaw_rad = w.yaw_rad;
    out.at_end = true;
  } else {
    size_t k = 0;
    out.position_m = point_at(s_target, &k);
    out.yaw_rad =
        config_.yaw_source == YawSource::kTangent ? tangent_yaw_[k] : waypoints_[k + 1].yaw_rad;
    if (config_.planar) {
      // planar points have no z: interpolate the waypoints' own
      const double len = arc_m_[k + 1] - arc_m_[k];
      const double t = len > kMinSegmentM ? (s_target - arc_m_[k]) / len : 0.0;
      out.position_m.z() =
          waypoints_[k].position.z + t * (waypoints_[k + 1].position.z - waypoints_[k].position.z);
    }
  }
  return out;
}

}  // namespace scancrew::path_tracker
