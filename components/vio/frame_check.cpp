#include "components/vio/frame_check.hpp"

#include <cmath>

namespace scancrew::vio {

namespace {

bool finite(const msg::Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

std::string_view to_string(InputError error) {
  switch (error) {
    case InputError::kNone:
      return "none";
    case InputError::kEmptyImage:
      return "empty image";
    case InputError::kSizeMismatch:
      return "left/right size mismatch";
    case InputError::kIntrinsicsMismatch:
      return "intrinsics do not match the image size";
    case InputError::kBadIntrinsics:
      return "invalid intrinsics";
    case InputError::kBadBaseline:
      return "invalid baseline";
    case InputError::kBadExtrinsics:
      return "invalid T_body_cam";
    case InputError::kStampNotIncreasing:
      return "stamp unset or not increasing";
    case InputError::kBadImu:
      return "non-finite IMU sample";
    case InputError::kBadWheelOdom:
      return "NaN or inf in a wheel-odometry velocity";
  }
  return "unknown";
}

InputError check_stereo(const msg::StereoFrame& frame) {
  const msg::CameraIntrinsics& k = frame.intrinsics;
  if (frame.left.empty() || frame.right.empty()) return InputError::kEmptyImage;
  if (frame.left.size() != frame.right.size()) return InputError::kSizeMismatch;
  if (k.width == 0 || k.height == 0 ||
      static_cast<uint64_t>(k.width) * k.height != frame.left.size())
    return InputError::kIntrinsicsMismatch;
  if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && k.fx > 0 && k.fy > 0 && std::isfinite(k.cx) &&
        std::isfinite(k.cy) && k.cx >= 0 && k.cy >= 0 && k.cx < k.width && k.cy < k.height))
    return InputError::kBadIntrinsics;
  if (!(std::isfinite(frame.baseline_m) && frame.baseline_m > 0)) return InputError::kBadBaseline;
  const msg::Quat& q = frame.T_body_cam.orientation;
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (!finite(frame.T_body_cam.position) || !std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3)
    return InputError::kBadExtrinsics;
  return InputError::kNone;
}

InputError check_imu(const msg::Imu& imu) {
  if (imu.header.stamp_ns == msg::kStampUnset || !finite(imu.linear_acceleration_mps2) ||
      !finite(imu.angular_velocity_radps))
    return InputError::kBadImu;
  return InputError::kNone;
}

}  // namespace scancrew::vio
