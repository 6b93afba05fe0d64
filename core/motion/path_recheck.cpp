#include "core/motion/path_recheck.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/motion/goal_check.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::motion {
namespace {

// The parameter of the point of segment [a, b] nearest p, in [0, 1].
double nearest_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = b - a;
  return ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
}

msg::Waypoint lerp(const msg::Waypoint& a, const msg::Waypoint& b, double t) {
  const Eigen::Vector3d p = (1 - t) * msg::to_eigen(a.position) + t * msg::to_eigen(b.position);
  msg::Waypoint w;
  w.position = msg::to_msg(p);
  w.yaw_rad = a.yaw_rad + t * wrap_angle(b.yaw_rad - a.yaw_rad);
  return w;
}

}  // namespace

size_t first_waypoint_ahead(std::span<const msg::Waypoint> path, const Eigen::Vector3d& position) {
  size_t from = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t k = 0; k + 1 < path.size(); ++k) {
    const Eigen::Vector3d a = msg::to_eigen(path[k].position);
    const Eigen::Vector3d b = msg::to_eigen(path[k + 1].position);
    const double t = nearest_on_segment(a, b, position);
    const double d = (a + t * (b - a) - position).squaredNorm();
    if (d < best) {
      best = d;
      from = k + 1;
    }
  }
  return from;
}

PathRecheck recheck_path(std::span<const msg::Waypoint> path, const Eigen::Vector3d& position,
                         double horizon_m, double step_m,
                         const std::function<bool(const msg::Waypoint&)>& is_free) {
  PathRecheck r;
  if (path.empty() || !(step_m > 0) || !(horizon_m > 0)) return r;
  const auto check = [&](const msg::Waypoint& w, double s) {
    ++r.poses_checked;
    if (is_free(w)) return true;
    r.blocked = true;
    r.blocked_at_m = s;
    r.where = msg::to_eigen(w.position);
    return false;
  };
  const size_t ahead = first_waypoint_ahead(path, position);
  if (ahead == 0) {  // a single waypoint: the goal
    (void)check(path.front(), 0);
    return r;
  }
  // from the robot's projection on its segment, then segment after segment
  const double t0 = nearest_on_segment(msg::to_eigen(path[ahead - 1].position),
                                       msg::to_eigen(path[ahead].position), position);
  double s = 0;  // arc length travelled along the path from the projection
  for (size_t k = ahead; k < path.size(); ++k) {
    const msg::Waypoint& a = path[k - 1];
    const msg::Waypoint& b = path[k];
    const double t_start = k == ahead ? t0 : 0.0;
    const double length = (msg::to_eigen(b.position) - msg::to_eigen(a.position)).norm();
    const double left = (1 - t_start) * length;
    // samples every step_m after the start of this piece (the robot's projection is not
    // checked), then its end
    for (double d = step_m; d < left; d += step_m) {
      if (s + d > horizon_m) return r;
      if (!check(lerp(a, b, length > 0 ? t_start + d / length : 1.0), s + d)) return r;
    }
    s += left;
    if (s > horizon_m) return r;
    if (!check(b, s)) return r;
  }
  return r;
}

}  // namespace scancrew::motion
