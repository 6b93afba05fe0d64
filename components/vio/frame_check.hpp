#pragma once

// Input checks of the VIO: a frame or IMU sample that fails one is skipped, counted under
// its reason and logged once per reason; it never reaches the tracker.

#include <array>
#include <cstdint>
#include <string_view>

#include "interfaces/sensor_msgs.hpp"

namespace scancrew::vio {

enum class InputError : uint8_t {
  kNone,
  kEmptyImage,          // no pixels, or a zero width/height
  kSizeMismatch,        // left and right images differ in size
  kIntrinsicsMismatch,  // width·height of the intrinsics is not the images' size
  kBadIntrinsics,       // focal length not finite and > 0, principal point off the image
  kBadBaseline,         // baseline not finite and > 0
  kBadExtrinsics,       // T_body_cam not finite, or not a unit quaternion
  kStampNotIncreasing,  // capture time unset or not after the previous frame's
  kBadImu,              // NaN or inf in an IMU sample, or an unset stamp
  kBadWheelOdom,        // NaN or inf in a wheel-odometry velocity
};
inline constexpr size_t kInputErrorCount = 10;
std::string_view to_string(InputError error);

// Per-reason counters.
using InputErrorCounts = std::array<uint64_t, kInputErrorCount>;

// Checks everything about a frame except its stamp's order. Allocates nothing.
InputError check_stereo(const msg::StereoFrame& frame);
InputError check_imu(const msg::Imu& imu);

}  // namespace scancrew::vio
