// Rendered sensors against geometry we know: depth to a wall, disparity of a point.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "tests/sim/sim_fixtures.hpp"

namespace scancrew::sim {
namespace {

using test::ground_robot;
using test::make_sim;
using test::wall_scene;

// camera centre: x = 0.25 m (mount_forward_m), so the wall's plane x = 2.9 is 2.65 m ahead
constexpr double kWallDepth = 2.65;

TEST(Rendering, DepthMatchesTheAnalyticDistanceToAWallWithin1mm) {
  auto sim = make_sim(wall_scene(), {ground_robot("r1", 0, 0)}, true);
  ASSERT_TRUE(sim);
  msg::StereoFrame stereo;
  msg::DepthImage depth;
  ASSERT_TRUE(sim->render_stereo(0, &stereo, &depth));
  const uint32_t w = depth.intrinsics.width, h = depth.intrinsics.height;
  ASSERT_EQ(depth.depth_m.size(), size_t{w} * h);
  // the upper half of the image sees only the wall (a plane facing the camera)
  double worst = 0;
  for (uint32_t y = 0; y < h / 2; ++y)
    for (uint32_t x = 0; x < w; ++x)
      worst = std::max(worst, std::abs(depth.depth_m[size_t{y} * w + x] - kWallDepth));
  EXPECT_LT(worst, 1e-3);
  // the pose comes with it: optical axis along world +x at the camera's position
  EXPECT_NEAR(depth.T_world_cam.position.x, 0.25, 1e-9);
  EXPECT_NEAR(depth.T_world_cam.position.z, 0.35, 1e-9);
  // the rig's extrinsics: optical z along body x, x along body -y, y along body -z
  EXPECT_NEAR(stereo.T_body_cam.position.x, 0.25, 1e-9);
  EXPECT_NEAR(stereo.T_body_cam.position.y, 0.0, 1e-9);
  EXPECT_NEAR(stereo.T_body_cam.position.z, 0.35, 1e-9);
  const msg::Quat& q = stereo.T_body_cam.orientation;
  const double sign = q.w < 0 ? -1 : 1;
  EXPECT_NEAR(sign * q.w, 0.5, 1e-9);
  EXPECT_NEAR(sign * q.x, -0.5, 1e-9);
  EXPECT_NEAR(sign * q.y, 0.5, 1e-9);
  EXPECT_NEAR(sign * q.z, -0.5, 1e-9);
}

TEST(Rendering, NoisyDepthWithNoiseOffEqualsGroundTruthInsideTheRange) {
  auto robot = ground_robot("r1", 0, 0);
  robot.camera.max_range_m = 2.0;  // the wall (2.65 m) is out of range
  auto sim = make_sim(wall_scene(), {robot}, true);
  ASSERT_TRUE(sim);
  msg::DepthImage depth;
  ASSERT_TRUE(sim->render_stereo(0, nullptr, &depth));
  msg::DepthImage gt = depth;
  sim->make_noisy_depth(0, depth);
  size_t compared = 0, beyond = 0;
  for (size_t i = 0; i < gt.depth_m.size(); ++i) {
    if (gt.depth_m[i] >= 0.3 && gt.depth_m[i] <= 2.0) {
      EXPECT_FLOAT_EQ(depth.depth_m[i], gt.depth_m[i]);
      ++compared;
    } else if (gt.depth_m[i] < 0.3) {
      EXPECT_TRUE(std::isnan(depth.depth_m[i]));  // REP 117: no measurement
    } else {
      EXPECT_EQ(depth.depth_m[i], std::numeric_limits<float>::infinity());  // beyond range
      ++beyond;
    }
  }
  EXPECT_GT(compared, 0u);  // the floor near the robot is in range
  EXPECT_GT(beyond, 0u);    // the wall is not
}

// Sub-pixel horizontal shift of a patch of the left image in the right image (SAD with
// a parabola through the three best costs).
double patch_disparity(const msg::StereoFrame& f, uint32_t cx, uint32_t cy, int half, int max_d) {
  const uint32_t w = f.intrinsics.width;
  std::vector<double> cost(static_cast<size_t>(max_d) + 1);
  for (int d = 0; d <= max_d; ++d) {
    double c = 0;
    for (int dy = -half; dy <= half; ++dy)
      for (int dx = -half; dx <= half; ++dx) {
        const size_t row = size_t(int(cy) + dy) * w;
        c += std::abs(int(f.left[row + size_t(int(cx) + dx)]) -
                      int(f.right[row + size_t(int(cx) + dx - d)]));
      }
    cost[static_cast<size_t>(d)] = c;
  }
  const auto best = static_cast<int>(std::min_element(cost.begin(), cost.end()) - cost.begin());
  if (best == 0 || best == max_d) return best;
  const double a = cost[best - 1], b = cost[best], c = cost[best + 1];
  return best + 0.5 * (a - c) / (a - 2 * b + c);
}

TEST(Rendering, DisparityOfAKnownPointEqualsFBOverZWithinHalfAPixel) {
  auto robot = ground_robot("r1", 0, 0);
  robot.camera.width = 640;
  robot.camera.height = 370;
  auto sim = make_sim(wall_scene(), {robot}, true);
  ASSERT_TRUE(sim);
  msg::StereoFrame stereo;
  ASSERT_TRUE(sim->render_stereo(0, &stereo, nullptr));
  const double expected = stereo.intrinsics.fx * stereo.baseline_m / kWallDepth;
  for (uint32_t cx : {200u, 320u, 440u}) {
    const double d = patch_disparity(stereo, cx, 100, 7, 60);
    EXPECT_NEAR(d, expected, 0.5) << "column " << cx;
  }
}

TEST(Rendering, ImagesHaveTextureForStereo) {
  auto sim = make_sim(wall_scene(), {ground_robot("r1", 0, 0)}, true);
  ASSERT_TRUE(sim);
  msg::StereoFrame stereo;
  ASSERT_TRUE(sim->render_stereo(0, &stereo, nullptr));
  double mean = 0, var = 0;
  for (uint8_t p : stereo.left) mean += p;
  mean /= static_cast<double>(stereo.left.size());
  for (uint8_t p : stereo.left) var += (p - mean) * (p - mean);
  EXPECT_GT(std::sqrt(var / stereo.left.size()), 10.0);  // not a flat image
}

// The grey-level spread of the upper half of the left image (the wall; the floor is below).
double upper_half_spread(const msg::StereoFrame& stereo) {
  const size_t n = stereo.left.size() / 2;
  double mean = 0, var = 0;
  for (size_t i = 0; i < n; ++i) mean += stereo.left[i];
  mean /= static_cast<double>(n);
  for (size_t i = 0; i < n; ++i) var += (stereo.left[i] - mean) * (stereo.left[i] - mean);
  return std::sqrt(var / static_cast<double>(n));
}

TEST(Rendering, APlainWallRendersFlatWhereADottedOneHasTexture) {
  SceneSpec scene = wall_scene();
  auto dotted = make_sim(scene, {ground_robot("r1", 0, 0)}, true);
  ASSERT_TRUE(dotted);
  scene.boxes[0].texture = SurfaceTexture::kPlain;
  auto plain = make_sim(scene, {ground_robot("r1", 0, 0)}, true);
  ASSERT_TRUE(plain);
  msg::StereoFrame a, b;
  ASSERT_TRUE(dotted->render_stereo(0, &a, nullptr));
  ASSERT_TRUE(plain->render_stereo(0, &b, nullptr));
  EXPECT_GT(upper_half_spread(a), 10.0);
  EXPECT_LT(upper_half_spread(b), 2.0);
}

}  // namespace
}  // namespace scancrew::sim
