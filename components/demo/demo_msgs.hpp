#pragma once

// Messages of the runtime demo graph only.

#include "interfaces/header.hpp"

namespace scancrew::demo {

// The horizontal shift between a stereo pair's images, found by block matching.
struct DisparityEstimate {
  static constexpr const char* kTypeName = "scancrew/demo/DisparityEstimate";
  msg::Header header;
  uint64_t frame_seq = 0;  // seq of the StereoFrame it was measured on
  int64_t frame_publish_mono_ns = 0;
  double disparity_px = 0;
  double depth_m = 0;  // f·B/d of that disparity
};

}  // namespace scancrew::demo
