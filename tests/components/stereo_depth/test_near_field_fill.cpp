// The near-field fill on depth images drawn analytically: a ground robot's camera (0.35 m
// up, level, the 320 x 185, 90 x 60 degree rig) before a wall, plain (NaN) or textured.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "components/stereo_depth/near_field_fill.hpp"

namespace scancrew::stereo_depth {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kCameraHeight = 0.35;
constexpr double kBlind = 0.65;  // f·B/64 for the ground rig

msg::CameraIntrinsics rig() {
  return {320, 185, 160.0, 160.0, 159.5, 92.0};
}

// The camera's optical frame (z forward, x right, y down) in the body frame (x forward, z up,
// the floor at z = 0).
Eigen::Isometry3d camera_in_body() {
  Eigen::Matrix3d axes;
  axes.col(0) = Eigen::Vector3d(0, -1, 0);
  axes.col(1) = Eigen::Vector3d(0, 0, -1);
  axes.col(2) = Eigen::Vector3d(1, 0, 0);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = axes;
  pose.translation() = Eigen::Vector3d(0, 0, kCameraHeight);
  return pose;
}

// What the camera sees: the floor, and a wall across the view `wall_m` ahead (0: none),
// plain (no depth on it) or textured; nothing nearer than the blind range or beyond 5 m.
// `hole` blanks the floor between those depths.
struct Scene {
  double wall_m = 0;
  bool plain = true;
  double hole_from_m = 0, hole_to_m = 0;
};

std::vector<float> draw(const Scene& s) {
  const msg::CameraIntrinsics k = rig();
  std::vector<float> depth(size_t{k.width} * k.height, kNaN);
  for (uint32_t v = 0; v < k.height; ++v) {
    const double down = (v - k.cy) / k.fy;  // the ray's drop per metre of depth
    for (uint32_t u = 0; u < k.width; ++u) {
      double z = down > 0 ? kCameraHeight / down : std::numeric_limits<double>::infinity();
      bool valid = !(z >= s.hole_from_m && z < s.hole_to_m);
      if (s.wall_m > 0 && s.wall_m < z) {
        z = s.wall_m;
        valid = !s.plain;
      }
      if (valid && z >= kBlind && z <= 5.0) depth[size_t{v} * k.width + u] = static_cast<float>(z);
    }
  }
  return depth;
}

// the height above the floor of pixel row v at depth z
double height_of(uint32_t v, double z) {
  return kCameraHeight - z * (v - rig().cy) / rig().fy;
}

TEST(NearFieldFill, APlainWallInTheNearFieldIsFilledAtTheFloorsEndUpToTheBodysHeight) {
  std::vector<float> depth = draw({.wall_m = 1.2});
  const NearFieldFillConfig config;
  const NearFieldFillStats stats = fill_near_field(depth, rig(), camera_in_body(), kBlind, config);
  EXPECT_EQ(stats.columns, rig().width);
  size_t on_wall = 0;  // pixels given a depth
  for (uint32_t v = 0; v < rig().height; ++v) {
    const double h = height_of(v, 1.2);
    if (h < 0) continue;  // the floor before the wall
    for (uint32_t u = 0; u < rig().width; ++u) {
      const float z = depth[size_t{v} * rig().width + u];
      if (h > config.max_height_m + 0.01) {
        EXPECT_TRUE(std::isnan(z)) << "row " << v;
      } else if (h < config.max_height_m - 0.01) {
        ASSERT_FALSE(std::isnan(z)) << "row " << v << " column " << u;
      }
      if (std::isnan(z)) continue;
      EXPECT_NEAR(z, 1.2, 0.03);  // the floor's end, within a row's spacing
      ++on_wall;
    }
  }
  EXPECT_EQ(stats.pixels, on_wall);
  EXPECT_GT(on_wall, 30u * rig().width);
}

TEST(NearFieldFill, ATexturedWallIsLeftAsItIs) {
  const std::vector<float> seen = draw({.wall_m = 1.2, .plain = false});
  std::vector<float> depth = seen;
  const NearFieldFillStats stats =
      fill_near_field(depth, rig(), camera_in_body(), kBlind, NearFieldFillConfig{});
  EXPECT_EQ(stats.columns, 0u);
  EXPECT_EQ(std::memcmp(depth.data(), seen.data(), depth.size() * sizeof(float)), 0);
}

TEST(NearFieldFill, APlainWallBeyondTheNearFieldIsLeftUnknown) {
  std::vector<float> depth = draw({.wall_m = 2.5});
  const NearFieldFillStats stats =
      fill_near_field(depth, rig(), camera_in_body(), kBlind, NearFieldFillConfig{});
  EXPECT_EQ(stats.columns, 0u);
}

TEST(NearFieldFill, AShortHoleInTheFloorsMatchIsNotAnObstacle) {
  // floor unmatched from 1.0 to 1.3 m, seen again beyond: 1.3 < 1.5 x 1.0
  std::vector<float> depth = draw({.hole_from_m = 1.0, .hole_to_m = 1.3});
  EXPECT_EQ(fill_near_field(depth, rig(), camera_in_body(), kBlind, NearFieldFillConfig{}).columns,
            0u);
  // unmatched from 1.0 to 1.6 m: the floor's end at 1.0 m behind something unseen
  depth = draw({.hole_from_m = 1.0, .hole_to_m = 1.6});
  EXPECT_EQ(fill_near_field(depth, rig(), camera_in_body(), kBlind, NearFieldFillConfig{}).columns,
            rig().width);
}

TEST(NearFieldFill, AFaceNearerThanTheBlindRangeIsNotFilled) {
  // no floor seen at all: filling at the blind range would carve free space through the face
  std::vector<float> depth = draw({.wall_m = 0.5});
  EXPECT_EQ(fill_near_field(depth, rig(), camera_in_body(), kBlind, NearFieldFillConfig{}).columns,
            0u);
}

TEST(NearFieldFill, ANearFieldOfZeroTurnsItOffAndBadValuesAreNamed) {
  std::vector<float> depth = draw({.wall_m = 1.2});
  NearFieldFillConfig config;
  config.range_m = 0;
  EXPECT_EQ(fill_near_field(depth, rig(), camera_in_body(), kBlind, config).columns, 0u);
  config.confirm_factor = 1.0;
  config.max_height_m = 0;
  const std::string e = config.validate();
  EXPECT_NE(e.find("near_field_confirm_factor must be > 1"), std::string::npos) << e;
  EXPECT_NE(e.find("near_field_max_height_m must be > 0"), std::string::npos) << e;
}

}  // namespace
}  // namespace scancrew::stereo_depth
