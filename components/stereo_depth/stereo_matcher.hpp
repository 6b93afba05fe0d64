#pragma once

// StereoMatcher: the disparity -> depth core of StereoDepth, without the runtime (so the
// benchmark and tests can call it directly). OpenCV stays in the .cpp.

#include <cstdint>
#include <memory>
#include <vector>

#include "components/stereo_depth/stereo_depth.hpp"

namespace scancrew::stereo_depth {

class StereoMatcher {
 public:
  StereoMatcher(const SgbmParams& params, double min_range_m, double max_range_m);
  ~StereoMatcher();
  StereoMatcher(const StereoMatcher&) = delete;
  StereoMatcher& operator=(const StereoMatcher&) = delete;

  // Depth (m along the optical axis, NaN where unknown) of the rectified pair; the images
  // are row-major 8-bit, width·height each. depth is resized to width·height.
  void compute(const uint8_t* left, const uint8_t* right, uint32_t width, uint32_t height,
               double fx_px, double baseline_m, std::vector<float>& depth);

  // The disparity search range used for this focal length and baseline (automatic: at most
  // kMaxAutoDisparities).
  uint32_t num_disparities(double fx_px, double baseline_m) const;
  static constexpr double kMaxAutoDisparities = 1024;  // num_disparities' configured maximum

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::stereo_depth
