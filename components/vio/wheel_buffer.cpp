#include "components/vio/wheel_buffer.hpp"

#include <algorithm>

namespace scancrew::vio {

bool WheelBuffer::add(int64_t stamp_ns, const Eigen::Vector3d& velocity_body_mps) {
  if (!readings_.empty() && stamp_ns <= readings_.back().stamp_ns) return false;
  readings_.push_back({stamp_ns, velocity_body_mps});
  return true;
}

std::optional<Eigen::Vector3d> WheelBuffer::mean_velocity(int64_t t0_ns, int64_t t1_ns) const {
  if (readings_.empty() || t1_ns <= t0_ns) return std::nullopt;
  if (readings_.front().stamp_ns > t0_ns + max_gap_ns_) return std::nullopt;
  if (readings_.back().stamp_ns < t1_ns - max_gap_ns_) return std::nullopt;
  // each reading holds from its stamp to the next one's (the last to t1)
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int64_t covered = 0;
  for (size_t i = 0; i < readings_.size(); ++i) {
    const int64_t from = std::max(readings_[i].stamp_ns, t0_ns);
    const int64_t to =
        std::min(i + 1 < readings_.size() ? readings_[i + 1].stamp_ns : t1_ns, t1_ns);
    if (to <= from) continue;
    sum += readings_[i].velocity_mps * static_cast<double>(to - from);
    covered += to - from;
  }
  if (covered == 0) return std::nullopt;
  return sum / static_cast<double>(covered);
}

void WheelBuffer::drop_before(int64_t t_ns) {
  // keep the last reading at or before t_ns: it holds into the next interval
  while (readings_.size() > 1 && readings_[1].stamp_ns <= t_ns) readings_.pop_front();
}

}  // namespace scancrew::vio
