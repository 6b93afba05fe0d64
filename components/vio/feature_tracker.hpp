#pragma once

// FeatureTracker: Shi-Tomasi corners on a grid (so they spread over the image) and
// pyramidal Lucas-Kanade tracking from one left image to the next — the front end of eVO
// (Sanfourche et al. 2013; thesis 1.2.2: Harris/Shi-Tomasi corners [Shi & Tomasi 1994]
// tracked with KLT [Baker & Matthews 2004]).
//
// The tracker keeps a copy of the last image it was given (the "previous" image);
// detect() finds corners in it and track() follows points from it into a new image,
// which then becomes the previous one. OpenCV stays in the .cpp. Not thread safe.
// Allocation: its own buffers keep their capacity; OpenCV allocates the image pyramids
// inside each track() call.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "components/vio/gray_image.hpp"

namespace scancrew::vio {

struct FeatureTrackerConfig {
  uint32_t max_features = 300;   // corners per keyframe, tracked ones included
  uint32_t grid_cols = 8;        // detection buckets: at most max_features/(cols·rows)
  uint32_t grid_rows = 4;        //   corners per cell, so the image is covered
  double quality_level = 0.005;  // Shi-Tomasi: min eigenvalue relative to the best corner
  double min_distance_px = 7.0;  // between corners (and from the points kept)
  uint32_t border_px = 8;        // no corner closer to the image border
  uint32_t klt_window_px = 11;   // KLT window side, odd (small: less perspective
                                 //   distortion of floor and ceiling texture)
  uint32_t klt_levels = 4;       // pyramid levels above the full image
  uint32_t klt_iterations = 30;  // per level
  double klt_max_error = 25.0;   // mean absolute patch difference (grey levels) to accept
};

class FeatureTracker {
 public:
  explicit FeatureTracker(const FeatureTrackerConfig& config);
  ~FeatureTracker();
  FeatureTracker(const FeatureTracker&) = delete;
  FeatureTracker& operator=(const FeatureTracker&) = delete;

  // Makes a copy of `image` the previous image (drops nothing else).
  void set_previous(GrayImage image);
  bool has_previous() const;

  // Corners of the previous image, at least min_distance_px from every point of `keep`,
  // best first within each grid cell, at most max_features - keep.size(). Appended to `out`.
  void detect(std::span<const Eigen::Vector2f> keep, std::vector<Eigen::Vector2f>& out) const;

  // Tracks `from` (positions in the previous image) into `image`. `to` holds initial
  // guesses on entry (a prediction, or `from` itself) and the tracked positions on return;
  // ok[i] says whether point i was tracked (converged, small error, inside the image).
  // Then `image` becomes the previous image. Returns the number tracked.
  size_t track(GrayImage image, std::span<const Eigen::Vector2f> from,
               std::vector<Eigen::Vector2f>& to, std::vector<uint8_t>& ok);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scancrew::vio
