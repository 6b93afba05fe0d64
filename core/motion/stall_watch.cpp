#include "core/motion/stall_watch.hpp"

#include "core/motion/path_recheck.hpp"
#include "interfaces/eigen_conversions.hpp"

namespace scancrew::motion {

bool StallWatch::update(double remaining_m, double now_s) {
  if (config_.timeout_s <= 0) return false;
  // progress: min_progress_m below the least way left so far (a NaN compares false)
  if (!best_ || remaining_m <= best_->remaining_m - config_.min_progress_m) {
    best_ = Best{.remaining_m = remaining_m, .at_s = now_s};
    return false;
  }
  if (now_s - best_->at_s < config_.timeout_s) return false;
  best_ = Best{.remaining_m = remaining_m, .at_s = now_s};
  return true;
}

double remaining_length_m(std::span<const msg::Waypoint> path, const Eigen::Vector3d& position,
                          bool planar) {
  if (path.empty()) return 0.0;
  const auto flat = [planar](Eigen::Vector3d p) {
    if (planar) p.z() = 0;
    return p;
  };
  const size_t ahead = first_waypoint_ahead(path, position);
  double length = (flat(msg::to_eigen(path[ahead].position)) - flat(position)).norm();
  for (size_t k = ahead + 1; k < path.size(); ++k)
    length +=
        (flat(msg::to_eigen(path[k].position)) - flat(msg::to_eigen(path[k - 1].position))).norm();
  return length;
}

}  // namespace scancrew::motion
