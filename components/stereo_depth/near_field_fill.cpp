#include "components/stereo_depth/near_field_fill.hpp"

#include <cmath>
#include <limits>

namespace scancrew::stereo_depth {

std::string NearFieldFillConfig::validate() const {
  std::string e;
  auto add = [&e](const std::string& m) { e += (e.empty() ? "" : "; ") + m; };
  if (!(range_m >= 0)) add("near_field_range_m must be >= 0");
  if (!(confirm_factor > 1)) add("near_field_confirm_factor must be > 1");
  if (!(floor_tolerance_m > 0)) add("near_field_floor_tolerance_m must be > 0");
  if (!(max_height_m > 0)) add("near_field_max_height_m must be > 0");
  return e;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One image column and the camera's geometry above the floor.
class ColumnScan {
 public:
  ColumnScan(std::vector<float>& depth, const msg::CameraIntrinsics& K,
             const Eigen::Isometry3d& T_floor_cam, uint32_t u)
      : depth_(depth),
        K_(K),
        R_(T_floor_cam.linear()),
        height_m_(T_floor_cam.translation().z()),
        u_(u) {}

  float& at(uint32_t v) { return depth_[size_t{v} * K_.width + u_]; }
  // the vertical component (floor frame) of the ray through row v, for a depth of 1 m
  double rise(uint32_t v) const {
    const Eigen::Vector3d ray_cam((u_ - K_.cx) / K_.fx, (v - K_.cy) / K_.fy, 1.0);
    return R_.row(2).dot(ray_cam);
  }
  // the depth at which row v's ray meets the floor; +inf at or above the horizon
  double floor_depth(uint32_t v) const {
    const double r = rise(v);
    return r < 0 ? height_m_ / -r : kInf;
  }
  // the height above the floor of row v's point at depth z
  double height_at(uint32_t v, double z) const { return height_m_ + z * rise(v); }

 private:
  std::vector<float>& depth_;
  const msg::CameraIntrinsics& K_;
  Eigen::Matrix3d R_;
  double height_m_;
  uint32_t u_;
};

// The invalid run starting at row v0 (its floor's end at depth d_m): true when it reaches
// rows meeting the floor at confirm_factor·d_m or beyond; `end` is the first row above v0
// that ended it (a valid pixel), or the row where it was confirmed.
bool run_confirmed(ColumnScan& c, uint32_t v0, double d_m, const NearFieldFillConfig& config,
                   uint32_t& end) {
  for (uint32_t v = v0 + 1; v-- > 0;) {
    end = v;
    if (std::isfinite(c.at(v))) return false;
    if (c.floor_depth(v) >= config.confirm_factor * d_m) return true;
  }
  return true;  // the image's top row still invalid (a camera looking down)
}

// Depth d_m for the invalid pixels from row v0 up, while their point is low enough.
uint32_t fill_run(ColumnScan& c, uint32_t v0, double d_m, const NearFieldFillConfig& config) {
  uint32_t filled = 0;
  for (uint32_t v = v0 + 1; v-- > 0;) {
    if (std::isfinite(c.at(v)) || c.height_at(v, d_m) > config.max_height_m) break;
    c.at(v) = static_cast<float>(d_m);
    ++filled;
  }
  return filled;
}

// One column, bottom up; the number of pixels filled.
uint32_t fill_column(ColumnScan& c, uint32_t height, double blind_range_m,
                     const NearFieldFillConfig& config) {
  bool floor_seen = false;
  for (uint32_t v = height; v-- > 0;) {
    const double d_m = c.floor_depth(v);
    if (!std::isfinite(d_m)) return 0;  // the horizon: no floor beyond
    if (d_m < blind_range_m) continue;
    const float z = c.at(v);
    if (std::isfinite(z)) {
      if (std::abs(c.height_at(v, z)) > config.floor_tolerance_m) return 0;  // a surface seen
      floor_seen = true;
      continue;
    }
    if (!floor_seen) continue;
    if (d_m > config.range_m) return 0;
    uint32_t end = v;
    if (run_confirmed(c, v, d_m, config, end)) return fill_run(c, v, d_m, config);
    v = end + 1;  // a hole in the floor's match: go on from the valid pixel that ended it
  }
  return 0;
}

}  // namespace

NearFieldFillStats fill_near_field(std::vector<float>& depth_m, const msg::CameraIntrinsics& K,
                                   const Eigen::Isometry3d& T_floor_cam, double blind_range_m,
                                   const NearFieldFillConfig& config) {
  NearFieldFillStats stats;
  if (config.range_m <= 0 || K.width == 0 || K.height == 0 || !(K.fx > 0) || !(K.fy > 0) ||
      depth_m.size() != size_t{K.width} * K.height || !(T_floor_cam.translation().z() > 0))
    return stats;
  for (uint32_t u = 0; u < K.width; ++u) {
    ColumnScan column(depth_m, K, T_floor_cam, u);
    const uint32_t n = fill_column(column, K.height, blind_range_m, config);
    if (n == 0) continue;
    ++stats.columns;
    stats.pixels += n;
  }
  return stats;
}

}  // namespace scancrew::stereo_depth
