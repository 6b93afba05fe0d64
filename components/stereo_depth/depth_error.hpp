#pragma once

// Depth error of an estimated depth image against ground truth of the same camera and
// instant (the simulator's depth_gt): the figures of `scancrew bench perception`.

#include <cstddef>
#include <vector>

namespace scancrew::stereo_depth {

struct DepthError {
  size_t reference_pixels = 0;  // ground truth valid and within [min_range, max_range]
  size_t valid_pixels = 0;      // of those, where the estimate has a depth
  double valid_ratio = 0;       // valid / reference
  double median_abs_m = 0;      // over valid pixels
  double median_rel = 0;        // |z - z_gt| / z_gt, over valid pixels
  double outlier_ratio = 0;     // share of valid pixels with relative error > outlier_rel
};

// Pixels where the ground truth is NaN or outside [min_range_m, max_range_m] are ignored.
DepthError depth_error(const std::vector<float>& estimate, const std::vector<float>& truth,
                       double min_range_m, double max_range_m, double outlier_rel = 0.05);

// Accumulates several frames: medians over all their pixels.
class DepthErrorAccumulator {
 public:
  void add(const std::vector<float>& estimate, const std::vector<float>& truth, double min_range_m,
           double max_range_m);
  DepthError result(double outlier_rel = 0.05) const;

 private:
  size_t reference_ = 0;
  std::vector<double> abs_, rel_;
};

}  // namespace scancrew::stereo_depth
