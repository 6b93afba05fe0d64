#pragma once

// SparseStereo: the depth of chosen left-image corners from a rectified pair, the
// keyframe step of eVO (thesis 1.2.2: "a 3D point-cloud is triangulated from a stereo
// image pair"). Each corner is searched along its row in the right image (SSD block
// matching over the disparities of [min_depth_m, max_depth_m], a uniqueness test, a
// parabola for the sub-pixel minimum), optionally refined by a one-level KLT left→right
// that must stay on the row, and triangulated: z = f·B/d (A.2.2).
//
// OpenCV stays in the .cpp. Not thread safe (scratch buffers, kept between calls).

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "components/vio/gray_image.hpp"
#include "interfaces/geometry.hpp"

namespace scancrew::vio {

struct SparseStereoConfig {
  uint32_t window_px = 9;    // SSD block and KLT window width, odd
  uint32_t window_rows = 5;  // their height, odd: short windows suffer less from the
                             //   vertical disparity gradient of the floor
  double min_depth_m = 0.3;  // disparities searched: f·B/max_depth .. f·B/min_depth
  double max_depth_m = 6.0;
  double uniqueness_ratio = 0.8;     // best SSD < ratio · best SSD more than 2 px away
  bool klt_refine = true;            // sub-pixel disparity from KLT left→right
  double max_row_error_px = 0.5;     // KLT: |y_right - y_left| allowed (rectified pair)
  double max_refine_shift_px = 1.5;  // KLT: |x_right - block-matching guess| allowed
};

struct StereoPoint {
  Eigen::Vector2f left_px;  // the corner in the left image
  Eigen::Vector3d p_cam;    // m, left optical frame
  float disparity_px = 0;
};

class SparseStereo {
 public:
  explicit SparseStereo(const SparseStereoConfig& config);
  ~SparseStereo();
  SparseStereo(const SparseStereo&) = delete;
  SparseStereo& operator=(const SparseStereo&) = delete;

  // Appends to `out` the corners that match, with their 3D points; returns how many.
  // `left` and `right` have the size of `intrinsics`.
  size_t match(GrayImage left, GrayImage right, const msg::CameraIntrinsics& intrinsics,
               double baseline_m, std::span<const Eigen::Vector2f> corners,
               std::vector<StereoPoint>& out);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::vio
