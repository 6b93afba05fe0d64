#include "components/low_level/stall_watch.hpp"

#include <cmath>
#include <numbers>

namespace scancrew::low_level {

bool StallWatch::update(const Eigen::Vector3d& position, double yaw_rad, double now_s) {
  if (config_.timeout_s <= 0) return false;
  const auto restart = [&] {
    since_ = Since{.position = position, .yaw_rad = yaw_rad, .at_s = now_s};
  };
  if (!since_) {
    restart();
    return false;
  }
  const double turned_deg =
      std::abs(std::remainder(yaw_rad - since_->yaw_rad, 2 * std::numbers::pi)) * 180.0 /
      std::numbers::pi;
  // a NaN pose counts as no motion: the watch then fires, and the planner plans again
  if ((position - since_->position).norm() >= config_.min_motion_m ||
      turned_deg >= config_.min_turn_deg) {
    restart();
    return false;
  }
  if (now_s - since_->at_s < config_.timeout_s) return false;
  restart();
  return true;
}

}  // namespace scancrew::low_level
