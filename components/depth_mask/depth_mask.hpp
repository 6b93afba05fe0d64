#pragma once

// DepthMask: blanks the depth pixels where teammates appear (thesis 5.2.2), so robots are
// not mapped as obstacles. A pixel is blanked (NaN) when its 3D point falls inside a
// teammate's body box grown by a margin; the teammates' poses come from their `pose` port
// (the remap applied in each teammate's namespace: pose: pose_gt gives /<ns>/pose_gt, pose:
// odom /<ns>/odom, for every other robot of the launch file), their body sizes from their kind.
//
// Body boxes, body frame (x forward, y left, z up): a ground robot's spans z from 0 (the
// floor under its centre) to its height; a multirotor's is centred on its body frame.

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "executors/component.hpp"
#include "executors/params.hpp"
#include "interfaces/nav_msgs.hpp"
#include "interfaces/sensor_msgs.hpp"

namespace scancrew::depth_mask {

class DepthMask final : public Component {
 public:
  static constexpr std::string_view kDescription =
      "blanks depth pixels on teammates (their poses and body sizes are known)";
  struct Config {
    std::vector<double> ground_body_m = {0.44, 0.40, 0.40};      // length, width, height
    std::vector<double> multirotor_body_m = {0.50, 0.50, 0.20};  // length, width, height
    double margin_m = 0.10;                                      // grows every box side
    double max_pose_age_s = 1.0;  // older teammate poses are not used (the mask would lag)
  };
  static Config read_config(ParamReader& p);

  DepthMask(ComponentContext context, Config config);

  uint64_t frames() const { return frames_; }
  uint64_t masked_pixels() const { return masked_; }
  // images dropped because their pixels do not match their intrinsics (logged once)
  uint64_t refused_frames() const { return refused_; }

 private:
  struct Teammate {
    std::string ns;
    std::array<double, 3> half{};    // half extents + margin
    std::array<double, 3> center{};  // box centre in the body frame
    msg::Pose3 T_world_body;
    int64_t stamp_ns = msg::kStampUnset;
  };

  Result<void, std::string> on_configure() override;
  void on_depth(Sample<msg::DepthImage>&& depth);

  Config config_;
  std::vector<Teammate> teammates_;
  Publisher<msg::DepthImage> out_;
  uint64_t frames_ = 0, masked_ = 0, refused_ = 0;
};

}  // namespace scancrew::depth_mask
