#include "sim/robot_model.hpp"

#include <cmath>

namespace scancrew::sim {

double CameraSpec::fx_px() const {
  // MuJoCo renders with the vertical FOV (MJCF fovy) over the image height; the horizontal
  // FOV follows from the width (square pixels), within the aspect tolerance of validate()
  return 0.5 * height / std::tan(fov_v_deg * M_PI / 360.0);
}

std::string CameraSpec::validate() const {
  if (width < 16 || height < 16 || width > 8192 || height > 8192)
    return "camera resolution " + std::to_string(width) + "x" + std::to_string(height) +
           " out of range; allowed: 16..8192 per side";
  if (!(baseline_m > 0) || baseline_m > 2) return "camera baseline_m must be in (0, 2]";
  if (!(fov_h_deg > 10 && fov_h_deg < 170) || !(fov_v_deg > 10 && fov_v_deg < 170))
    return "camera field of view out of range; allowed: (10, 170) degrees each way";
  // MuJoCo renders square pixels: the aspect ratio fixes one FOV from the other
  const double aspect = std::tan(fov_h_deg * M_PI / 360.0) / std::tan(fov_v_deg * M_PI / 360.0);
  const double image_aspect = static_cast<double>(width) / height;
  if (std::abs(aspect / image_aspect - 1.0) > 0.02) {
    const auto h = static_cast<uint32_t>(std::lround(width / aspect));
    return "camera " + std::to_string(width) + "x" + std::to_string(height) + " cannot show " +
           std::to_string(fov_h_deg) + " x " + std::to_string(fov_v_deg) +
           " degrees with square pixels; for this width use height " + std::to_string(h);
  }
  if (!(min_range_m > 0) || !(max_range_m > min_range_m))
    return "camera range must satisfy 0 < min < max";
  if (!(rate_hz > 0) || rate_hz > 1000) return "camera rate_hz must be in (0, 1000]";
  return {};
}

CameraSpec default_camera(RobotKind kind) {
  CameraSpec c;
  if (kind == RobotKind::kMultirotor) {
    c.baseline_m = 0.11;
    c.min_range_m = 1.6;
    c.max_range_m = 8.0;
    c.mount_up_m = 0.0;
  }
  return c;
}

}  // namespace scancrew::sim
