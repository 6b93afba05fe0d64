#include "components/vio/imu_buffer.hpp"

#include <algorithm>
#include <cmath>

namespace scancrew::vio {

bool ImuBuffer::add(int64_t stamp_ns, const Eigen::Vector3d& accel_mps2,
                    const Eigen::Vector3d& gyro_radps) {
  if (!samples_.empty() && stamp_ns <= samples_.back().stamp_ns) return false;
  samples_.push_back({stamp_ns, accel_mps2, gyro_radps});
  return true;
}

std::optional<Eigen::Quaterniond> ImuBuffer::rotation(int64_t t0_ns, int64_t t1_ns) const {
  if (samples_.empty() || t1_ns < t0_ns) return std::nullopt;
  // the rate holds from a sample's stamp to the next; before the first sample, the first
  // one's rate is held back in time (a bounded gap, checked below)
  if (samples_.front().stamp_ns - t0_ns > max_gap_ns_) return std::nullopt;
  if (t1_ns - samples_.back().stamp_ns > max_gap_ns_) return std::nullopt;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  // the last sample at or before t0 (or the first one)
  auto it = std::upper_bound(samples_.begin(), samples_.end(), t0_ns,
                             [](int64_t t, const Sample& s) { return t < s.stamp_ns; });
  if (it != samples_.begin()) --it;
  int64_t t = t0_ns;
  for (; it != samples_.end() && t < t1_ns; ++it) {
    const auto next = std::next(it);
    const int64_t end = next == samples_.end() ? t1_ns : std::min(next->stamp_ns, t1_ns);
    if (end <= t) continue;
    if (end - t > max_gap_ns_) return std::nullopt;
    const Eigen::Vector3d angle = it->gyro_radps * (static_cast<double>(end - t) * 1e-9);
    const double norm = angle.norm();
    if (norm > 1e-12) q = q * Eigen::Quaterniond(Eigen::AngleAxisd(norm, angle / norm));
    t = end;
  }
  return q.normalized();
}

std::optional<Eigen::Vector3d> ImuBuffer::mean_accel(int64_t t_ns, int64_t window_ns) const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  size_t n = 0;
  for (const Sample& s : samples_) {
    if (s.stamp_ns <= t_ns - window_ns || s.stamp_ns > t_ns) continue;
    sum += s.accel_mps2;
    ++n;
  }
  if (n == 0) return std::nullopt;
  return sum / static_cast<double>(n);
}

void ImuBuffer::drop_before(int64_t t_ns) {
  // keep the last sample at or before t_ns: its rate holds into [t_ns, ...)
  while (samples_.size() >= 2 && samples_[1].stamp_ns <= t_ns) samples_.pop_front();
}

Eigen::Quaterniond gravity_aligned_attitude(const Eigen::Vector3d& accel_body_mps2,
                                            double yaw_rad) {
  // tilt: the smallest rotation taking the measured up to the world's +z; it leaves the
  // heading of the body's x axis unchanged to first order, and the launch's yaw sets it
  const Eigen::Quaterniond tilt =
      Eigen::Quaterniond::FromTwoVectors(accel_body_mps2.normalized(), Eigen::Vector3d::UnitZ());
  // the yaw of the tilted body's x axis, replaced by yaw_rad
  const Eigen::Vector3d x = tilt * Eigen::Vector3d::UnitX();
  const double current_yaw = std::atan2(x.y(), x.x());
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad - current_yaw, Eigen::Vector3d::UnitZ())) *
         tilt;
}

}  // namespace scancrew::vio
