// Odometry error on synthetic trajectories whose errors are known in closed form.

#include <gtest/gtest.h>

#include <cmath>

#include "eval/odometry_error.hpp"

namespace scancrew::eval {
namespace {

msg::Pose3 pose(double x, double y, double z, double yaw) {
  msg::Pose3 p;
  p.position = {x, y, z};
  p.orientation = {std::cos(yaw / 2), 0, 0, std::sin(yaw / 2)};
  return p;
}

// A straight line along x, 0.125 m per pose (binary-exact, so segments are exactly L long).
std::vector<StampedPose> line(size_t n, double scale = 1.0) {
  std::vector<StampedPose> t;
  for (size_t i = 0; i < n; ++i)
    t.push_back({static_cast<int64_t>(i) * 100'000'000,
                 pose(0.125 * static_cast<double>(i) * scale, 0, 0, 0)});
  return t;
}

// A circle of radius 2 m, heading along the tangent.
std::vector<StampedPose> circle(size_t n) {
  std::vector<StampedPose> t;
  for (size_t i = 0; i < n; ++i) {
    const double a = 0.05 * static_cast<double>(i);
    t.push_back(
        {static_cast<int64_t>(i) * 100'000'000, pose(2 * std::sin(a), 2 - 2 * std::cos(a), 0, a)});
  }
  return t;
}

TEST(OdometryError, AnExactEstimateHasNoError) {
  const auto gt = circle(100);
  const auto r = odometry_error(gt, gt);
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->matched, 100u);
  EXPECT_NEAR(r->ate_rmse_m, 0, 1e-12);
  EXPECT_NEAR(r->rpe_max_percent, 0, 1e-9);
  EXPECT_GT(r->segments, 0u);
  EXPECT_NEAR(r->distance_m, 99 * 4 * std::sin(0.025), 1e-9);  // 99 chords of a 2 m circle
}

TEST(OdometryError, AConstantScaleDriftGivesThatDriftAsRpe) {
  // 2 % too long: every metre of true motion is estimated as 1.02 m
  const auto gt = line(81), est = line(81, 1.02);
  const auto r = odometry_error(est, gt, {.segment_length_m = 1.0});
  ASSERT_TRUE(r) << r.error();
  EXPECT_NEAR(r->distance_m, 10.0, 1e-9);
  EXPECT_EQ(r->segments, 81u - 8u);
  EXPECT_NEAR(r->rpe_mean_percent, 2.0, 1e-9);
  EXPECT_NEAR(r->rpe_max_percent, 2.0, 1e-9);
  EXPECT_NEAR(r->rpe_rotation_deg_per_m, 0.0, 1e-9);
  // ATE of a scale drift: RMS of 0.02 x over x = 0, 0.125, .., 10
  double sum2 = 0;
  for (int i = 0; i <= 80; ++i) sum2 += std::pow(0.02 * 0.125 * i, 2);
  EXPECT_NEAR(r->ate_rmse_m, std::sqrt(sum2 / 81), 1e-9);
  EXPECT_NEAR(r->ate_max_m, 0.2, 1e-9);
}

TEST(OdometryError, AConstantOffsetIsAllAteAndNoRpe) {
  const auto gt = circle(100);
  auto est = gt;
  for (StampedPose& p : est) {
    p.pose.position.x += 0.3;
    p.pose.position.z -= 0.4;
  }
  const auto r = odometry_error(est, gt);
  ASSERT_TRUE(r) << r.error();
  EXPECT_NEAR(r->ate_rmse_m, 0.5, 1e-9);
  EXPECT_NEAR(r->ate_max_m, 0.5, 1e-9);
  EXPECT_NEAR(r->rpe_max_percent, 0, 1e-9);
}

TEST(OdometryError, AlignmentRemovesARigidOffset) {
  const auto gt = circle(100);
  auto est = gt;
  // the whole estimate turned by 0.3 rad about z and shifted
  const double c = std::cos(0.3), s = std::sin(0.3);
  for (StampedPose& p : est) {
    const msg::Vec3 q = p.pose.position;
    p.pose.position = {c * q.x - s * q.y + 1.0, s * q.x + c * q.y - 2.0, q.z};
  }
  EXPECT_GT(odometry_error(est, gt)->ate_rmse_m, 0.5);
  for (const Alignment a : {Alignment::kSe3, Alignment::kYaw}) {
    const auto r = odometry_error(est, gt, {.alignment = a});
    ASSERT_TRUE(r) << r.error();
    EXPECT_NEAR(r->ate_rmse_m, 0, 1e-9) << to_string(a);
  }
}

TEST(OdometryError, MatchesByStampAndSkipsPosesWithoutGroundTruth) {
  const auto gt = line(41);
  std::vector<StampedPose> est;
  // every other stamp, shifted by 1 ms, in reverse order
  for (size_t i = 41; i-- > 0;)
    if (i % 2 == 0) est.push_back({gt[i].stamp_ns + 1'000'000, gt[i].pose});
  est.push_back({999'000'000'000, pose(0, 0, 0, 0)});  // no ground truth near it
  EXPECT_FALSE(odometry_error(est, gt));               // exact stamps by default
  const auto r = odometry_error(est, gt, {.max_stamp_difference_ns = 2'000'000});
  ASSERT_TRUE(r) << r.error();
  EXPECT_EQ(r->matched, 21u);
  EXPECT_NEAR(r->ate_rmse_m, 0, 1e-12);
  EXPECT_NEAR(r->distance_m, 5.0, 1e-9);
}

TEST(OdometryError, RefusesBadInput) {
  const auto gt = line(10);
  EXPECT_FALSE(odometry_error({}, gt));
  EXPECT_FALSE(odometry_error(gt, gt, {.segment_length_m = 0}));
  auto bad = gt;
  bad[3].pose.position.y = std::nan("");
  const auto r = odometry_error(bad, gt);
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("not finite"), std::string::npos);
  // a trajectory shorter than L has ATE but no RPE segment
  const auto s = odometry_error(gt, gt, {.segment_length_m = 100});
  ASSERT_TRUE(s);
  EXPECT_EQ(s->segments, 0u);
}

}  // namespace
}  // namespace scancrew::eval
