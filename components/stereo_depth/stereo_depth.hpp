#pragma once

// StereoDepth: depth from a rectified grayscale stereo pair with OpenCV's semi-global
// matcher (the thesis used ELAS; 1.2.2, 5.2.2). z = f·B/d; pixels without a disparity,
// filtered out (uniqueness, speckles, left-right check) or outside the camera range are
// NaN. Publishes `depth` stamped with the capture time and the camera pose at that time.
//
// The pose comes from the `pose` port (remap pose: pose_gt, the simulator's oracle, or pose:
// odom, the vio component's): frames wait for the pose of their stamp (bounded), poses
// with tracking lost drop their frame. The camera pose is T_world_body · T_body_cam (the
// rig's extrinsics travel with each StereoFrame).
//
// On a ground robot, invalid depth just beyond the floor it sees is filled as an obstacle
// (near_field_fill.hpp; docs/perception.md, "Near-field fill"): a plain wall would leave
// no depth at all.

#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <string_view>

#include "components/stereo_depth/near_field_fill.hpp"
#include "core/enum_names.hpp"
#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::stereo_depth {

// OpenCV's SGBM variant (param `mode`): 5 paths, 8 paths (full two-pass) or 3-way.
enum class SgbmMode : uint8_t { kSgbm, kHh, kSgbm3Way };

inline constexpr EnumNames<SgbmMode, 3> kSgbmModeNames = {
    {{SgbmMode::kSgbm, "sgbm"}, {SgbmMode::kHh, "hh"}, {SgbmMode::kSgbm3Way, "sgbm_3way"}}};

struct SgbmParams {
  // multiple of 16; 0: f·B/min_range (every depth in range, but the leftmost that many
  // columns cannot be matched: 144 of 320 for a ground robot at 0.3 m). 64 sees from
  // f·B/64 = 0.65 m on for the 320-pixel, 0.26 m ground robot rig.
  uint32_t num_disparities = 64;
  uint32_t block_size = 5;             // odd, 1..11
  uint32_t p1 = 0, p2 = 0;             // smoothness penalties; 0: 8·block² and 32·block²
  uint32_t uniqueness_ratio = 10;      // % margin of the best cost over the second best
  uint32_t speckle_window_size = 100;  // px; 0 disables the speckle filter
  uint32_t speckle_range = 2;          // disparity variation inside a speckle, px
  int32_t disp12_max_diff = 1;         // left-right check, px; < 0 disables
  uint32_t pre_filter_cap = 63;
  SgbmMode mode = SgbmMode::kSgbm;  // sgbm (5 paths) | hh (8 paths) | sgbm_3way
  // Texture check (as OpenCV's block matcher's textureThreshold, which SGBM lacks): a pixel
  // whose texture_window² window of the left image has a mean |Sobel x| below
  // texture_threshold (grey levels) is NaN. 0: off.
  double texture_threshold = 2.0;
  uint32_t texture_window = 9;  // odd, 3..31
};

// Bad-input counters: every skipped frame is counted under its reason.
struct StereoDepthStats {
  uint64_t frames = 0, published = 0;
  uint64_t empty = 0, size_mismatch = 0, intrinsics_mismatch = 0, no_pose = 0, pose_lost = 0;
  // the near-field fill (ground robots): images, columns and pixels it filled
  uint64_t filled_images = 0, filled_columns = 0, filled_pixels = 0;
};

class StereoMatcher;  // OpenCV inside

class StereoDepth final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "depth from the stereo pair (OpenCV SGBM), with the camera pose at capture";
  struct Config {
    SgbmParams sgbm;
    double min_range_m = 0.3, max_range_m = 5.0;  // thesis table 5.3
    uint32_t max_pending_frames = 4;              // frames waiting for their pose
    uint32_t pose_history = 64;                   // poses kept for frames still to come
    NearFieldFillConfig near_field;               // ground robots only
  };
  static Config read_config(ParamReader& p);

  StereoDepth(ComponentContext context, Config config);
  ~StereoDepth() override;

  const StereoDepthStats& stats() const { return stats_; }

 private:
  Result<void, std::string> on_configure() override;
  void on_deactivate() override;
  void on_frame(Sample<msg::StereoFrame>&& frame);
  void on_pose(Sample<msg::Odometry>&& pose);
  void process_ready();
  void compute(const msg::StereoFrame& frame, const msg::Odometry& pose);
  bool valid(const msg::StereoFrame& frame);

  Config config_;
  bool fill_near_field_ = false;  // a ground robot with near_field.range_m > 0
  std::unique_ptr<StereoMatcher> matcher_;
  Publisher<msg::DepthImage> depth_;
  std::deque<Sample<msg::StereoFrame>> pending_;
  std::deque<Sample<msg::Odometry>> poses_;
  StereoDepthStats stats_;
};

}  // namespace scancrew::stereo_depth
