#include <gtest/gtest.h>

#include <cmath>

#include "sim/depth_noise.hpp"

namespace scancrew::sim {
namespace {

struct Stats {
  double mean, stddev;
};

Stats stats_of(const std::vector<float>& v, uint32_t w, uint32_t h) {
  // interior only: the border has fewer neighbours in the smoothing
  double sum = 0, sq = 0;
  size_t n = 0;
  for (uint32_t y = 1; y + 1 < h; ++y)
    for (uint32_t x = 1; x + 1 < w; ++x) {
      const double z = v[size_t{y} * w + x];
      sum += z;
      sq += z * z;
      ++n;
    }
  const double mean = sum / n;
  return {mean, std::sqrt(sq / n - mean * mean)};
}

TEST(DepthNoise, SigmaFollowsTheThesisModel) {
  // sigma(z) = |e_d| z^2 / (f B) with Table 2.1's e_d 0.1 px, f 376 px, B 0.11 m: 3.87 cm at
  // 4 m and 15.47 cm at the Powerplant's far range, 8 m (worked by hand)
  EXPECT_NEAR(depth_sigma_m(4.0, 0.1, 376, 0.11), 0.038685, 1e-6);
  EXPECT_NEAR(depth_sigma_m(8.0, 0.1, 376, 0.11), 0.154739, 1e-6);
  EXPECT_DOUBLE_EQ(depth_sigma_m(2.0, -0.1, 100, 0.1), depth_sigma_m(2.0, 0.1, 100, 0.1));
}

TEST(DepthNoise, NoiseHasTheModelledSpreadAndSmoothingReducesIt) {
  const uint32_t w = 200, h = 200;
  const double z = 4.0, sigma = depth_sigma_m(z, 0.1, 160, 0.26);
  DepthNoiseParams p{.add_noise = true,
                     .disparity_error_px = 0.1,
                     .fx_px = 160,
                     .baseline_m = 0.26,
                     .smoothing = false,
                     .min_range_m = 0.3,
                     .max_range_m = 10};
  std::mt19937_64 rng(3);
  std::vector<float> scratch, raw(size_t{w} * h, static_cast<float>(z));
  apply_depth_noise(raw, w, h, p, rng, scratch);
  const Stats noisy = stats_of(raw, w, h);
  EXPECT_NEAR(noisy.mean, z, 3 * sigma / std::sqrt(w * h));
  EXPECT_NEAR(noisy.stddev, sigma, 0.03 * sigma);
  // a [1 2 1]x[1 2 1]/16 kernel keeps sqrt(36/256) = 0.375 of white noise's spread
  p.smoothing = true;
  std::vector<float> smooth(size_t{w} * h, static_cast<float>(z));
  apply_depth_noise(smooth, w, h, p, rng, scratch);
  EXPECT_NEAR(stats_of(smooth, w, h).stddev, 0.375 * sigma, 0.05 * sigma);
}

TEST(DepthNoise, OutOfRangeFollowsRep117AndDoesNotLeakIntoNeighbours) {
  const uint32_t w = 4, h = 1;
  // in range; nothing up to the far plane (NaN from the renderer); beyond max; below min
  std::vector<float> d = {1.0f, std::numeric_limits<float>::quiet_NaN(), 50.0f, 0.1f}, scratch;
  DepthNoiseParams p{.add_noise = true, .smoothing = true, .min_range_m = 0.3, .max_range_m = 5};
  p.fx_px = 100;
  p.baseline_m = 0.1;
  std::mt19937_64 rng(1);
  apply_depth_noise(d, w, h, p, rng, scratch);
  EXPECT_TRUE(std::isfinite(d[0]));
  EXPECT_NEAR(d[0], 1.0f, 0.1f);  // its neighbours are not finite: not averaged in
  EXPECT_EQ(d[1], std::numeric_limits<float>::infinity());
  EXPECT_EQ(d[2], std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(d[3]));
}

}  // namespace
}  // namespace scancrew::sim
