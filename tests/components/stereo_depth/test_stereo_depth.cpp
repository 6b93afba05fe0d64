// Stereo depth on the sim backend against the simulator's ground-truth depth, and every
// kind of bad frame counted and skipped.

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "components/stereo_depth/depth_error.hpp"
#include "components/stereo_depth/stereo_depth.hpp"
#include "components/stereo_depth/stereo_matcher.hpp"
#include "executors/launch.hpp"
#include "executors/registry.hpp"

namespace scancrew::stereo_depth {
namespace {

// Pairs each depth image with the ground truth of the same stamp.
class DepthPairs final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: pairs depth with depth_gt";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  DepthPairs(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

  std::map<int64_t, msg::DepthImage> estimate, truth;

 private:
  Result<void, std::string> on_configure() override {
    create_subscription<msg::DepthImage>(
        "depth", {.depth = 8},
        [this](Sample<msg::DepthImage>&& s) { estimate[s->header.stamp_ns] = *s; });
    create_subscription<msg::DepthImage>(
        "depth_gt", {.depth = 8},
        [this](Sample<msg::DepthImage>&& s) { truth[s->header.stamp_ns] = *s; });
    return {};
  }
};
SCANCREW_REGISTER_COMPONENT(DepthPairs, "test_depth_pairs")

// Publishes crafted frames and poses: one per tick, from a script.
class Feeder final : public Component {
 public:
  static constexpr std::string_view kDescription = "test: publishes bad stereo frames";
  struct Config {};
  static Config read_config(ParamReader& /*p*/) { return {}; }
  Feeder(ComponentContext c, Config /*config*/) : Component(std::move(c)) {}

 private:
  Result<void, std::string> on_configure() override {
    stereo_ = create_publisher<msg::StereoFrame>("stereo");
    pose_ = create_publisher<msg::Odometry>("pose_gt");
    create_timer(std::chrono::milliseconds(100), [this] { tick(); });
    return {};
  }
  void tick() {
    const int64_t stamp = int64_t{++step_} * 100'000'000;
    auto f = stereo_.loan();
    ASSERT_TRUE(f);
    msg::StereoFrame& frame = **f;
    frame.header.stamp_ns = stamp;
    frame.intrinsics = {64, 32, 32, 32, 31.5, 15.5};
    frame.baseline_m = 0.26;
    frame.left.assign(size_t{64} * 32, 100);
    frame.right.assign(size_t{64} * 32, 100);
    bool with_pose = true;
    double quality = 1;
    switch (step_) {
      case 1:
        frame.left.clear();
        break;  // empty
      case 2:
        frame.right.resize(10);
        break;  // size mismatch
      case 3:
        frame.intrinsics.width = 50;
        break;  // camera model mismatch
      case 4:
        frame.baseline_m = 0;
        break;  // camera model mismatch
      case 5:
        quality = 0;
        break;  // tracking lost
      case 6:
        with_pose = false;
        break;  // its pose never comes
      default:
        break;  // fine
    }
    (void)stereo_.publish(std::move(*f));
    if (!with_pose) return;
    auto p = pose_.loan();
    ASSERT_TRUE(p);
    (*p)->header.stamp_ns = stamp;
    (*p)->tracking_quality = quality;
    (void)pose_.publish(std::move(*p));
  }
  Publisher<msg::StereoFrame> stereo_;
  Publisher<msg::Odometry> pose_;
  int step_ = 0;
};
SCANCREW_REGISTER_COMPONENT(Feeder, "test_bad_frame_feeder")

TEST(StereoDepth, DepthMatchesGroundTruthWithin2PercentUpTo5m) {
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 2.0, sim_step_s: 0.05}
robots:
  - {id: 1, namespace: r1, kind: ground, start: [-3.0, -2.5, 0, 30]}
remap: {pose: pose_gt}
components:
  - name: sim
    type: team_simulator
    per_robot: false
    params:
      scene: )" SCANCREW_SOURCE_DIR R"(/launch_cfg/scenes/test_arena.yaml
      publish_depth: false
      publish_depth_gt: true
      ground_camera_rate_hz: 5
  - {name: stereo, type: stereo_depth, params: {}}
  - {name: pairs, type: test_depth_pairs}
)",
                                    "stereo.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  auto* pairs = (*launch)->find_component<DepthPairs>();
  ASSERT_NE(pairs, nullptr);
  ASSERT_EQ(pairs->estimate.size(), 10u);
  DepthErrorAccumulator acc;
  for (const auto& [stamp, est] : pairs->estimate) {
    ASSERT_TRUE(pairs->truth.count(stamp)) << stamp;
    const msg::DepthImage& gt = pairs->truth.at(stamp);
    // the camera pose at capture: the same as the simulator's
    EXPECT_NEAR(est.T_world_cam.position.x, gt.T_world_cam.position.x, 1e-9);
    EXPECT_NEAR(est.T_world_cam.position.y, gt.T_world_cam.position.y, 1e-9);
    EXPECT_NEAR(est.T_world_cam.position.z, gt.T_world_cam.position.z, 1e-9);
    EXPECT_NEAR(std::abs(est.T_world_cam.orientation.w * gt.T_world_cam.orientation.w +
                         est.T_world_cam.orientation.x * gt.T_world_cam.orientation.x +
                         est.T_world_cam.orientation.y * gt.T_world_cam.orientation.y +
                         est.T_world_cam.orientation.z * gt.T_world_cam.orientation.z),
                1.0, 1e-9);
    acc.add(est.depth_m, gt.depth_m, 0.65, 5.0);
  }
  const DepthError e = acc.result();
  RecordProperty("median_rel", std::to_string(e.median_rel));
  RecordProperty("valid_ratio", std::to_string(e.valid_ratio));
  std::printf(
      "depth vs ground truth (0.65-5 m): median rel %.4f, median abs %.4f m, valid %.3f, "
      "outliers %.3f over %zu pixels\n",
      e.median_rel, e.median_abs_m, e.valid_ratio, e.outlier_ratio, e.reference_pixels);
  EXPECT_GT(e.reference_pixels, 100000u);
  EXPECT_LE(e.median_rel, 0.02);
  EXPECT_GE(e.valid_ratio, 0.6);
  EXPECT_LE(e.outlier_ratio, 0.1);
}

TEST(StereoDepth, BadFramesAreCountedAndSkipped) {
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 1.05, sim_step_s: 0.05}
robots: [{id: 1, namespace: r1}]
remap: {pose: pose_gt}
components:
  - {name: feeder, type: test_bad_frame_feeder}
  - {name: stereo, type: stereo_depth, params: {num_disparities: 16, max_pending_frames: 2}}
)",
                                    "bad.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  auto* stereo = (*launch)->find_component<StereoDepth>();
  ASSERT_NE(stereo, nullptr);
  const StereoDepthStats& s = stereo->stats();
  EXPECT_EQ(s.frames, 10u);
  EXPECT_EQ(s.empty, 1u);
  EXPECT_EQ(s.size_mismatch, 1u);
  EXPECT_EQ(s.intrinsics_mismatch, 2u);
  EXPECT_EQ(s.pose_lost, 1u);
  EXPECT_EQ(s.no_pose, 1u);
  EXPECT_EQ(s.published, 4u);  // frames 7 to 10
}

// The automatic disparity range comes from the frame's camera model, so it is bounded:
// a focal length of 1e12 px (a forged frame) asked for 1e11 disparities.
TEST(StereoMatcher, TheAutomaticDisparityRangeIsBounded) {
  const StereoMatcher matcher(SgbmParams{.num_disparities = 0}, 0.3, 5.0);
  EXPECT_EQ(matcher.num_disparities(320, 0.1), 112U);  // 320 x 0.1 / 0.3 = 106.7 -> 112
  EXPECT_EQ(matcher.num_disparities(1e12, 0.1), 1024U);
  EXPECT_EQ(matcher.num_disparities(std::nan(""), 0.1), 16U);
}

// A pair whose left half is random dots and right half one flat grey, the right image the
// left shifted by 8 px (depth f·B/8). SGBM carries disparities into the flat half; the
// texture check leaves it NaN and keeps the dotted half.
TEST(StereoMatcher, TheTextureCheckLeavesAPlainFaceWithoutDepth) {
  constexpr size_t kW = 192, kH = 96, kShift = 8;
  std::vector<uint8_t> left(kW * kH, 150), right(kW * kH, 150);
  uint32_t state = 12345;
  for (size_t y = 0; y < kH; ++y)
    for (size_t x = 0; x < kW / 2; ++x) {
      state = state * 1664525u + 1013904223u;
      left[y * kW + x] = (state >> 24) & 1 ? 240 : 60;
    }
  for (size_t y = 0; y < kH; ++y)
    for (size_t x = 0; x + kShift < kW; ++x) right[y * kW + x] = left[y * kW + x + kShift];
  const double fx = 100, baseline = 0.2;  // f·B/8 = 2.5 m
  const auto count = [&](double threshold, size_t x0, size_t x1, size_t& valid,
                         size_t& near_truth) {
    SgbmParams p{.num_disparities = 32};
    p.texture_threshold = threshold;
    StereoMatcher matcher(p, 0.3, 10.0);
    std::vector<float> depth;
    matcher.compute(left.data(), right.data(), static_cast<uint32_t>(kW), static_cast<uint32_t>(kH),
                    fx, baseline, depth);
    valid = near_truth = 0;
    for (size_t y = 8; y + 8 < kH; ++y)
      for (size_t x = x0; x < x1; ++x) {
        const float z = depth[y * kW + x];
        if (std::isnan(z)) continue;
        ++valid;
        near_truth += std::abs(z - 2.5) < 0.1 ? 1 : 0;
      }
  };
  size_t valid = 0, near_truth = 0;
  count(0, kW / 2 + 16, kW - 16, valid, near_truth);  // the flat half, no check
  RecordProperty("flat_valid_without_check", std::to_string(valid));
  count(2.0, kW / 2 + 16, kW - 16, valid, near_truth);
  EXPECT_EQ(valid, 0u);
  count(2.0, 48, kW / 2 - 16, valid, near_truth);  // the dotted half, with the check
  const size_t area = (kH - 16) * (kW / 2 - 64);
  EXPECT_GT(near_truth, area * 9 / 10) << valid << " valid of " << area;
}

TEST(StereoDepth, BadParametersAreErrors) {
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
robots: [{id: 1, namespace: r1}]
remap: {pose: pose_gt}
components:
  - {name: stereo, type: stereo_depth, params: {num_disparities: 50, block_size: 4, min_range_m: 3, max_range_m: 2, pose_source: vio, texture_window: 4, near_field_confirm_factor: 0.5}}
)",
                                    "bad_params.yaml");
  ASSERT_FALSE(launch);
  std::string all;
  for (const auto& e : launch.error()) all += e + "\n";
  EXPECT_NE(all.find("num_disparities: must be a multiple of 16"), std::string::npos) << all;
  EXPECT_NE(all.find("block_size: must be odd"), std::string::npos) << all;
  EXPECT_NE(all.find("max_range_m: must be greater than min_range_m"), std::string::npos) << all;
  EXPECT_NE(all.find("texture_window: must be odd"), std::string::npos) << all;
  EXPECT_NE(all.find("near_field_confirm_factor: 0.5 is out of range"), std::string::npos) << all;
  // the pose comes by remap now: the old key is refused by name
  EXPECT_NE(all.find("pose_source: unknown parameter"), std::string::npos) << all;
}

}  // namespace
}  // namespace scancrew::stereo_depth
