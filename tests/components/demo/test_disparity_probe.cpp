#include <gtest/gtest.h>

#include "components/demo/demo_monitor.hpp"
#include "components/demo/disparity_probe.hpp"
#include "executors/launch.hpp"

namespace scancrew::demo {
namespace {

msg::StereoFrame random_dot_pair(uint32_t w, uint32_t h, uint32_t d) {
  msg::StereoFrame f;
  f.intrinsics = {w, h, 100, 100, w / 2.0, h / 2.0};
  f.left.resize(size_t{w} * h);
  f.right.resize(size_t{w} * h);
  uint32_t state = 12345;
  std::vector<uint8_t> row(w + d);
  for (uint32_t y = 0; y < h; ++y) {
    for (auto& px : row) px = static_cast<uint8_t>((state = state * 1664525u + 1013904223u) >> 24);
    for (uint32_t x = 0; x < w; ++x) {
      f.left[size_t{y} * w + x] = row[x];
      f.right[size_t{y} * w + x] = row[x + d];
    }
  }
  return f;
}

TEST(DisparityProbe, FindsTheShiftOfARandomDotPair) {
  for (uint32_t d : {1u, 7u, 16u, 40u})
    EXPECT_EQ(DisparityProbe::best_shift(random_dot_pair(128, 32, d), 48, 16), static_cast<int>(d));
}

TEST(DisparityProbe, RejectsImagesNarrowerThanTheSearchRange) {
  EXPECT_EQ(DisparityProbe::best_shift(random_dot_pair(32, 8, 4), 48, 8), -1);
  msg::StereoFrame empty;
  EXPECT_EQ(DisparityProbe::best_shift(empty, 4, 4), -1);
}

TEST(DemoGraph, EveryEstimateIsCorrectOnSimTime) {
  auto launch = Launch::from_string(R"(
clock: sim
executor: {type: step}
run: {duration_s: 1.0, sim_step_s: 0.01}
robots: [{id: 1, namespace: r1}]
components:
  - {name: camera, type: demo_camera, params: {rate_hz: 20, width: 160, height: 48, disparity_px: 9}}
  - {name: probe, type: disparity_probe, params: {max_disparity_px: 20, band_rows: 16}}
  - {name: monitor, type: demo_monitor, params: {expected_disparity_px: 9}}
)",
                                    "demo.yaml");
  ASSERT_TRUE(launch) << launch.error().front();
  (*launch)->run();
  const auto& monitor = dynamic_cast<const DemoMonitor&>(*(*launch)->components().back());
  EXPECT_EQ(monitor.received(), 20u);
  EXPECT_EQ(monitor.correct(), 20u);
  EXPECT_EQ(monitor.frames_lost(), 0u);
}

}  // namespace
}  // namespace scancrew::demo
